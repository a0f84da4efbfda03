/* tdm_scurve.c: the S-curve planner (see tdm_scurve.h). A line-by-line port of
 * tdm_stepper::model::scurve and model::poly's validation; docs/model.md ("The S-curve
 * planner") describes the method. */
#include "tdm_scurve.h"
#include <math.h>

#define RATE_ONE 4294967296.0       /* 2^32 */
#define SPLIT_TICKS 8388608.0       /* 2^23: longer phases are split */
#define MIN_PIECE_TICKS 64u         /* a boundary closer than this to the one before is dropped */
#define POLY_MAX_T_TICKS (1ul << 24)
#define MAX_STEPS (1l << 24)
#define MAX_V0_RATE 0x7FFFFFFFul
#define BISECTION_STEPS 100
#define MAX_PHASES 15

typedef struct {
    double dur, jerk, snap;
} phase;

typedef struct {
    unsigned count;
    phase phases[MAX_PHASES];
    double starts[MAX_PHASES + 1][4]; /* t, x, v, a at each phase start, and at the end */
} profile;

typedef struct {
    double accel, jerk, snap; /* snap 0: third order */
} side_limits;

typedef struct {
    uint64_t tick;
    int64_t pos;
    double ts;
    uint32_t rate;
    double acc;
    int snap; /* the piece ending here overlaps a phase with snap */
} boundary;

int tdm_poly_check(const tdm_poly_segment *seg, uint32_t max_rate)
{
    int64_t n, t, v0t, v1t, a, b1, b2, hull;
    if (seg->t_ticks == 0) return 1;
    if (seg->t_ticks > POLY_MAX_T_TICKS) return 4;
    n = seg->steps < 0 ? -(int64_t)seg->steps : (int64_t)seg->steps;
    if (n > MAX_STEPS) return 5;
    if (seg->v0_rate > MAX_V0_RATE || seg->v1_rate > MAX_V0_RATE) return 6;
    /* Control points x3 of the speed x T.2^32: b1 = 3.v0.T + 2A,
     * b2 = 12n.2^32 - 6.v0.T - 3.v1.T - 2A. With |A| >= 2^60 one of them is negative. */
    a = seg->a_q32;
    if (a >= ((int64_t)1 << 60) || a <= -((int64_t)1 << 60)) return 2;
    t = (int64_t)seg->t_ticks;
    v0t = (int64_t)seg->v0_rate * t;
    v1t = (int64_t)seg->v1_rate * t;
    b1 = 3 * v0t + 2 * a;
    b2 = 12 * (n << 32) - 6 * v0t - 3 * v1t - 2 * a;
    if (b1 < 0 || b2 < 0) return 2;
    hull = 3 * (int64_t)max_rate * t;
    if (seg->v0_rate > max_rate || seg->v1_rate > max_rate || b1 > hull || b2 > hull) return 3;
    return 0;
}

static void advance(const double s[4], const phase *p, double tau, double out[4])
{
    double t2 = tau * tau;
    double t3 = t2 * tau;
    double j = p->jerk, q = p->snap;
    out[0] = s[0] + tau;
    out[1] = s[1] + s[2] * tau + s[3] * t2 / 2.0 + j * t3 / 6.0 + q * t3 * tau / 24.0;
    out[2] = s[2] + s[3] * tau + j * t2 / 2.0 + q * t3 / 6.0;
    out[3] = s[3] + j * tau + q * t2 / 2.0;
}

static void profile_new(profile *pr, double v_start, const phase *ph, unsigned count)
{
    double s[4] = {0.0, 0.0, 0.0, 0.0};
    unsigned k;
    s[2] = v_start;
    pr->count = 0;
    for (k = 0; k < count; k++) {
        if (ph[k].dur > 0.0) pr->phases[pr->count++] = ph[k];
    }
    for (k = 0; k < pr->count; k++) {
        double next[4];
        pr->starts[k][0] = s[0];
        pr->starts[k][1] = s[1];
        pr->starts[k][2] = s[2];
        pr->starts[k][3] = s[3];
        advance(s, &pr->phases[k], pr->phases[k].dur, next);
        s[0] = next[0];
        s[1] = next[1];
        s[2] = next[2];
        s[3] = next[3];
    }
    pr->starts[pr->count][0] = s[0];
    pr->starts[pr->count][1] = s[1];
    pr->starts[pr->count][2] = s[2];
    pr->starts[pr->count][3] = s[3];
}

/* (x, v, a) at time t, clamped to the profile. */
static void state_at(const profile *pr, double t, double out[4])
{
    unsigned k = 0;
    int i;
    double tau;
    if (pr->count == 0) {
        out[0] = pr->starts[0][0];
        out[1] = pr->starts[0][1];
        out[2] = pr->starts[0][2];
        out[3] = pr->starts[0][3];
        return;
    }
    for (i = (int)pr->count - 1; i >= 0; i--) {
        if (pr->starts[i][0] <= t) {
            k = (unsigned)i;
            break;
        }
    }
    tau = t - pr->starts[k][0];
    if (tau < 0.0) tau = 0.0;
    if (tau > pr->phases[k].dur) tau = pr->phases[k].dur;
    advance(pr->starts[k], &pr->phases[k], tau, out);
}

static double position_at(const profile *pr, double t)
{
    double s[4];
    state_at(pr, t, s);
    return s[1];
}

static double rise(double ap, double j, double s)
{
    return ap * s <= j * j ? 2.0 * sqrt(ap / s) : ap / j + j / s;
}

/* A change of x whose own rate is limited to `limit` and whose rate's rate is r (a
 * speed change: dv, a, j; an acceleration ramp: ap, j, s): the ramp time and the hold
 * at the limit. */
static void ramp(double x, double limit, double r, double *t_ramp, double *t_hold)
{
    if (x * r <= limit * limit) {
        *t_ramp = sqrt(x / r);
        *t_hold = 0.0;
    } else {
        *t_ramp = limit / r;
        *t_hold = x / limit - limit / r;
    }
}

/* The phases of a speed change of dv with sign (+1 up, -1 down); returns their count. */
static unsigned speed_change(double dv, const side_limits *l, double sign, phase *out)
{
    double a = l->accel, j = l->jerk, s = l->snap;
    if (dv <= 0.0) return 0;
    if (s == 0.0) {
        double tj, th;
        ramp(dv, a, j, &tj, &th);
        out[0].dur = tj, out[0].jerk = sign * j, out[0].snap = 0.0;
        out[1].dur = th, out[1].jerk = 0.0, out[1].snap = 0.0;
        out[2].dur = tj, out[2].jerk = -sign * j, out[2].snap = 0.0;
        return 3;
    } else {
        double ap, th, ts, tjh, js, q;
        int i;
        if (a * rise(a, j, s) <= dv) {
            ap = a;
            th = (dv - a * rise(a, j, s)) / a;
        } else {
            double lo = 0.0, hi = a;
            for (i = 0; i < BISECTION_STEPS; i++) {
                double mid = (lo + hi) / 2.0;
                if (mid * rise(mid, j, s) <= dv) lo = mid;
                else hi = mid;
            }
            ap = lo;
            th = 0.0;
        }
        ramp(ap, j, s, &ts, &tjh);
        js = sign * s * ts;
        q = sign * s;
        out[0].dur = ts, out[0].jerk = 0.0, out[0].snap = q;
        out[1].dur = tjh, out[1].jerk = js, out[1].snap = 0.0;
        out[2].dur = ts, out[2].jerk = js, out[2].snap = -q;
        out[3].dur = th, out[3].jerk = 0.0, out[3].snap = 0.0;
        out[4].dur = ts, out[4].jerk = 0.0, out[4].snap = -q;
        out[5].dur = tjh, out[5].jerk = -js, out[5].snap = 0.0;
        out[6].dur = ts, out[6].jerk = -js, out[6].snap = q;
        return 7;
    }
}

static double phases_duration(const phase *p, unsigned count)
{
    double sum = 0.0;
    unsigned k;
    for (k = 0; k < count; k++) sum += p[k].dur;
    return sum;
}

static double need(double vp, double v0, double v1, const side_limits *up, const side_limits *down)
{
    phase acc[7], dec[7];
    unsigned na = speed_change(vp - v0, up, 1.0, acc);
    unsigned nd = speed_change(vp - v1, down, -1.0, dec);
    return (v0 + vp) / 2.0 * phases_duration(acc, na) + (vp + v1) / 2.0 * phases_duration(dec, nd);
}

static int build_profile(profile *pr, double dist, double v0, double v1, double vmax, const side_limits *up,
                         const side_limits *down)
{
    double floor_v = v0 > v1 ? v0 : v1, vp, cruise;
    phase all[MAX_PHASES];
    unsigned count;
    int i;
    if (need(floor_v, v0, v1, up, down) > dist) return TDM_SCURVE_E_TOO_SHORT;
    if (need(vmax, v0, v1, up, down) <= dist) {
        vp = vmax;
        cruise = (dist - need(vmax, v0, v1, up, down)) / vmax;
    } else {
        double lo = floor_v, hi = vmax;
        for (i = 0; i < BISECTION_STEPS; i++) {
            double mid = (lo + hi) / 2.0;
            if (need(mid, v0, v1, up, down) <= dist) lo = mid;
            else hi = mid;
        }
        vp = lo;
        cruise = 0.0;
    }
    count = speed_change(vp - v0, up, 1.0, all);
    all[count].dur = cruise, all[count].jerk = 0.0, all[count].snap = 0.0;
    count++;
    count += speed_change(vp - v1, down, -1.0, all + count);
    profile_new(pr, v0, all, count);
    return 0;
}

static int limit_ok(double v, int zero_ok)
{
    return isfinite(v) && (v > 0.0 || (zero_ok && v == 0.0));
}

static uint32_t to_rate(double v, double f)
{
    double r = round(v / f * RATE_ONE);
    if (!(r > 0.0)) return 0; /* negative or NaN: 0, as Rust's saturating cast */
    if (r > 4294967295.0) return 0xFFFFFFFFul;
    return (uint32_t)r;
}

static double time_of(const profile *pr, double x, double total_s)
{
    double lo = 0.0, hi = total_s;
    int i;
    for (i = 0; i < BISECTION_STEPS; i++) {
        double mid = (lo + hi) / 2.0;
        if (position_at(pr, mid) < x) lo = mid;
        else hi = mid;
    }
    return hi;
}

/* Segment k (1-based) from boundaries b. */
static void make(const boundary *b, unsigned k, int snap, int64_t sign, tdm_poly_segment *out)
{
    const boundary *s = &b[k - 1], *e = &b[k];
    uint32_t t = (uint32_t)(e->tick - s->tick);
    out->v0_rate = s->rate;
    out->v1_rate = e->rate;
    out->t_ticks = t;
    out->steps = (int32_t)(sign * (e->pos - s->pos));
    if (snap) {
        out->a_q32 = (int64_t)round(s->acc * (double)t * (double)t / 2.0 * RATE_ONE);
    } else {
        int64_t n = e->pos - s->pos;
        out->a_q32 = 3 * (n << 32) - (2 * (int64_t)s->rate + (int64_t)e->rate) * (int64_t)t;
    }
}

static int valid_piece(const boundary *b, unsigned k, int snap, int64_t sign, uint32_t max_rate)
{
    tdm_poly_segment seg;
    make(b, k, snap, sign, &seg);
    return tdm_poly_check(&seg, max_rate) == 0;
}

/* Does moving the rate at boundary `which` by delta make piece k (and, when which is
 * k - 1, piece k - 1) valid? The rate is restored. */
static int try_delta(boundary *b, unsigned k, unsigned which, int64_t delta, int snap, const int *snaps, int64_t sign,
                     uint32_t max_rate)
{
    int64_t r = (int64_t)b[which].rate + delta;
    uint32_t keep = b[which].rate;
    int ok;
    if (r < 0 || r > (int64_t)max_rate) return 0;
    b[which].rate = (uint32_t)r;
    ok = valid_piece(b, k, snap, sign, max_rate) && (which == k || valid_piece(b, k - 1, snaps[k - 1], sign, max_rate));
    b[which].rate = keep;
    return ok;
}

static int plan(int32_t steps, double v_start, double v_end, double v_max, const side_limits *up,
                const side_limits *down, uint32_t clock_hz, uint32_t max_rate, tdm_poly_segment *out, unsigned *count)
{
    profile pr;
    boundary b[TDM_SCURVE_MAX_SEGMENTS + 2];
    int snaps[TDM_SCURVE_MAX_SEGMENTS + 2];
    unsigned nb = 0, k, i, last;
    double f, f2, total_s;
    uint64_t total;
    int64_t n, sign;
    int rc;
    *count = 0;
    if (!limit_ok(v_max, 0) || !limit_ok(v_start, 1) || !limit_ok(v_end, 1) || clock_hz == 0)
        return TDM_SCURVE_E_BAD_LIMIT;
    if (v_start > v_max || v_end > v_max) return TDM_SCURVE_E_BAD_LIMIT;
    f = (double)clock_hz;
    if (to_rate(v_max, f) > max_rate) return 3;
    n = steps < 0 ? -(int64_t)steps : (int64_t)steps;
    if (n == 0) return 0;
    rc = build_profile(&pr, (double)n, v_start, v_end, v_max, up, down);
    if (rc) return rc;
    total_s = pr.starts[pr.count][0];
    total = (uint64_t)round(total_s * f);
    /* Boundaries: each phase end (long phases split), moved to the nearest whole step. */
    b[0].tick = 0, b[0].pos = 0, b[0].ts = 0.0;
    nb = 1;
    for (k = 0; k < pr.count; k++) {
        double t0 = pr.starts[k][0], t1 = pr.starts[k + 1][0];
        double p = ceil((t1 - t0) * f / SPLIT_TICKS);
        uint64_t parts = p > 1.0 ? (uint64_t)p : 1;
        uint64_t j;
        for (j = 1; j <= parts; j++) {
            double t, ts;
            int64_t xs;
            uint64_t tick;
            if (k + 1 == pr.count && j == parts) break; /* the move's end */
            t = t0 + (t1 - t0) * (double)j / (double)parts;
            xs = (int64_t)round(position_at(&pr, t));
            if (xs <= b[nb - 1].pos || xs >= n) continue;
            ts = time_of(&pr, (double)xs, total_s);
            tick = (uint64_t)round(ts * f);
            if (tick < b[nb - 1].tick + MIN_PIECE_TICKS || tick + MIN_PIECE_TICKS > total) continue;
            if (nb >= TDM_SCURVE_MAX_SEGMENTS + 1) return TDM_SCURVE_E_TOO_MANY;
            b[nb].tick = tick, b[nb].pos = xs, b[nb].ts = ts;
            nb++;
        }
    }
    b[nb].tick = total, b[nb].pos = n, b[nb].ts = total_s;
    nb++;
    if (nb - 1 > TDM_SCURVE_MAX_SEGMENTS) return TDM_SCURVE_E_TOO_MANY;
    snaps[0] = 0;
    for (k = 1; k < nb; k++) {
        double t0 = b[k - 1].ts, t1 = b[k].ts;
        snaps[k] = 0;
        for (i = 0; i < pr.count; i++) {
            if (pr.phases[i].snap != 0.0 && pr.starts[i][0] < t1 && pr.starts[i + 1][0] > t0) snaps[k] = 1;
        }
        if (b[k].tick - b[k - 1].tick > POLY_MAX_T_TICKS) return TDM_SCURVE_E_TOO_SLOW;
    }
    f2 = f * f;
    for (k = 0; k < nb; k++) {
        double s[4];
        state_at(&pr, b[k].ts, s);
        b[k].rate = to_rate(s[2], f);
        b[k].acc = s[3] / f2;
    }
    b[0].rate = to_rate(v_start, f);
    b[nb - 1].rate = to_rate(v_end, f);
    sign = steps < 0 ? -1 : 1;
    last = nb - 1;
    for (k = 1; k < nb; k++) {
        int forms[2], nforms = 0, f_i, chosen = -1;
        if (snaps[k]) forms[nforms++] = 1;
        forms[nforms++] = 0;
        for (f_i = 0; f_i < nforms; f_i++) {
            if (valid_piece(b, k, forms[f_i], sign, max_rate)) {
                chosen = forms[f_i];
                break;
            }
        }
        if (chosen < 0) {
            int have = 0, best_snap = 0;
            int64_t best_hi = 0, best_delta = 0;
            unsigned best_which = 0;
            for (f_i = 0; f_i < nforms; f_i++) {
                unsigned w;
                for (w = 0; w < 2; w++) {
                    unsigned which = w == 0 ? k : k - 1;
                    int e, found = 0;
                    int64_t sg = 0;
                    if (which == 0 || which == last) continue;
                    for (e = 0; e < 32 && !found; e++) {
                        if (try_delta(b, k, which, -((int64_t)1 << e), forms[f_i], snaps, sign, max_rate)) {
                            sg = -1, found = 1;
                        } else if (try_delta(b, k, which, (int64_t)1 << e, forms[f_i], snaps, sign, max_rate)) {
                            sg = 1, found = 1;
                        }
                    }
                    if (found) {
                        int64_t lo, hi;
                        e--; /* the exponent that was found */
                        lo = e == 0 ? 0 : (int64_t)1 << (e - 1);
                        hi = (int64_t)1 << e;
                        while (hi - lo > 1) {
                            int64_t mid = lo + (hi - lo) / 2;
                            if (try_delta(b, k, which, sg * mid, forms[f_i], snaps, sign, max_rate)) hi = mid;
                            else lo = mid;
                        }
                        if (!have || hi < best_hi) {
                            have = 1;
                            best_hi = hi;
                            best_delta = sg * hi;
                            best_snap = forms[f_i];
                            best_which = which;
                        }
                        break;
                    }
                }
            }
            if (have) {
                b[best_which].rate = (uint32_t)((int64_t)b[best_which].rate + best_delta);
                if (best_which == k - 1) make(b, k - 1, snaps[k - 1], sign, &out[k - 2]);
                chosen = best_snap;
            }
        }
        snaps[k] = chosen > 0;
        make(b, k, snaps[k], sign, &out[k - 1]);
    }
    for (k = 0; k + 1 < nb; k++) {
        rc = tdm_poly_check(&out[k], max_rate);
        if (rc) {
            *count = k;
            return rc;
        }
    }
    *count = nb - 1;
    return 0;
}

int tdm_plan_jerk(int32_t steps, double v_start, double v_end, double v_max, double a_max, double j_max,
                  double d_max, double jd_max, uint32_t clock_hz, uint32_t max_rate, tdm_poly_segment *out,
                  unsigned *count)
{
    side_limits up, down;
    *count = 0;
    if (!limit_ok(a_max, 0) || !limit_ok(j_max, 0) || !limit_ok(d_max, 0) || !limit_ok(jd_max, 0))
        return TDM_SCURVE_E_BAD_LIMIT;
    up.accel = a_max, up.jerk = j_max, up.snap = 0.0;
    down.accel = d_max, down.jerk = jd_max, down.snap = 0.0;
    return plan(steps, v_start, v_end, v_max, &up, &down, clock_hz, max_rate, out, count);
}

int tdm_plan_fourth(int32_t steps, double v_max, double a_max, double j_max, double s_max, uint32_t clock_hz,
                    uint32_t max_rate, tdm_poly_segment *out, unsigned *count)
{
    side_limits side;
    *count = 0;
    if (!limit_ok(a_max, 0) || !limit_ok(j_max, 0) || !limit_ok(s_max, 0)) return TDM_SCURVE_E_BAD_LIMIT;
    side.accel = a_max, side.jerk = j_max, side.snap = s_max;
    return plan(steps, 0.0, 0.0, v_max, &side, &side, clock_hz, max_rate, out, count);
}
