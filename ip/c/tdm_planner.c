/* tdm_planner.c: the move planner. See tdm_planner.h; every step mirrors
 * tdm_stepper::model::planner (trapezoid_by_ticks, trapezoid_by_rates). */
#include "tdm_planner.h"

/* An unsigned 128-bit value as two halves, for the few products that need it. */
typedef struct {
    uint64_t hi;
    uint64_t lo;
} u128_t;

static u128_t mul64(uint64_t a, uint64_t b)
{
    uint64_t a0 = a & 0xFFFFFFFFu, a1 = a >> 32, b0 = b & 0xFFFFFFFFu, b1 = b >> 32;
    uint64_t p00 = a0 * b0, p01 = a0 * b1, p10 = a1 * b0, p11 = a1 * b1;
    uint64_t mid = (p00 >> 32) + (p01 & 0xFFFFFFFFu) + (p10 & 0xFFFFFFFFu);
    u128_t r;
    r.lo = (mid << 32) | (p00 & 0xFFFFFFFFu);
    r.hi = p11 + (p01 >> 32) + (p10 >> 32) + (mid >> 32);
    return r;
}

static int le128(u128_t a, u128_t b)
{
    return a.hi < b.hi || (a.hi == b.hi && a.lo <= b.lo);
}

/* Splits total into parts proportional to w (largest remainder, ties to the lower
 * phase). total <= 3 * 2^24 and each w < 2^34, so every product fits 64 bits. */
static void apportion(uint64_t total, const uint64_t w[3], uint64_t parts[3])
{
    uint64_t sum = w[0] + w[1] + w[2];
    uint64_t rem[3];
    int taken[3] = {0, 0, 0};
    uint64_t given = 0;
    unsigned k;
    for (k = 0; k < 3u; k++) {
        uint64_t exact = total * w[k];
        parts[k] = exact / sum;
        rem[k] = exact % sum;
        given += parts[k];
    }
    while (given < total) {
        unsigned best = 3u;
        for (k = 0; k < 3u; k++) {
            if (!taken[k] && (best == 3u || rem[k] > rem[best])) {
                best = k;
            }
        }
        taken[best] = 1;
        parts[best] += 1u;
        given += 1u;
    }
}

int tdm_plan_ticks(int32_t steps, const uint32_t phase_ticks[3], uint32_t max_rate,
                   tdm_segment out[3], unsigned *count, unsigned *bad_phase)
{
    uint64_t n_total;
    uint64_t w[3];
    uint64_t parts[3];
    uint64_t v_end_rate = 0;
    unsigned k;
    *count = 0u;
    *bad_phase = 0u;
    if ((uint64_t)phase_ticks[0] + phase_ticks[1] + phase_ticks[2] == 0u) {
        return TDM_PLAN_E_NO_DURATION;
    }
    n_total = steps < 0 ? (uint64_t)(-(int64_t)steps) : (uint64_t)steps;
    if (n_total == 0u) {
        /* No motion: one dwell per non-empty phase. */
        for (k = 0; k < 3u; k++) {
            if (phase_ticks[k] > 0u) {
                tdm_segment d;
                int rc;
                d.v0_rate = 0u;
                d.t_ticks = phase_ticks[k];
                d.steps = 0;
                rc = tdm_segment_check(&d, max_rate);
                if (rc != 0) {
                    *bad_phase = k;
                    *count = 0u;
                    return rc;
                }
                out[(*count)++] = d;
            }
        }
        return 0;
    }
    if (n_total > 3u * TDM_MAX_STEPS) {
        return TDM_PLAN_E_TOO_MANY_STEPS;
    }
    /* Area weights in half-ticks: accelerate T/2, cruise T, decelerate T/2. */
    w[0] = phase_ticks[0];
    w[1] = 2u * (uint64_t)phase_ticks[1];
    w[2] = phase_ticks[2];
    apportion(n_total, w, parts);
    for (k = 0; k < 3u; k++) {
        if (parts[k] > TDM_MAX_STEPS) {
            return TDM_PLAN_E_TOO_MANY_STEPS;
        }
    }
    for (k = 0; k < 3u; k++) {
        uint64_t t = phase_ticks[k];
        uint64_t n = parts[k];
        uint64_t no_reverse;
        uint64_t v0;
        uint64_t v_end_t;
        tdm_segment seg;
        int rc;
        if (t == 0u) {
            continue;
        }
        /* Highest start rate that does not reverse: v0·T <= 2n·2^32. */
        no_reverse = ((2u * n) << 32) / t;
        v0 = v_end_rate < no_reverse ? v_end_rate : no_reverse;
        if (v0 > 0xFFFFFFFFu) {
            v0 = 0xFFFFFFFFu;
        }
        seg.v0_rate = (uint32_t)v0;
        seg.t_ticks = (uint32_t)t;
        seg.steps = steps < 0 ? -(int32_t)n : (int32_t)n;
        rc = tdm_segment_check(&seg, max_rate);
        if (rc != 0) {
            *bad_phase = k;
            *count = 0u;
            return rc;
        }
        /* The end speed, rounded to the rate unit: v_end·T·2^32 >= 0 here. */
        v_end_t = ((2u * n) << 32) - v0 * t;
        v_end_rate = (v_end_t + t / 2u) / t;
        out[(*count)++] = seg;
    }
    return 0;
}

/* round(num / den), half up. */
static uint64_t div_round(uint64_t num, uint64_t den)
{
    return (2u * num + den) / (2u * den);
}

/* The triangle's phase of rate x (the other y): the largest T < 2^31 with
 * (2T - 1)^2 · x(x + y) <= 8n·y·f^2, by bisection. */
static uint64_t triangle_phase_ticks(uint64_t n, uint64_t x, uint64_t y, uint64_t f)
{
    u128_t rhs = mul64(8u * n * y, f * f);
    uint64_t xx = x * (x + y);
    uint64_t lo = 0u, hi = (1ull << 31) - 1u;
    uint64_t wh = 2u * hi - 1u;
    if (le128(mul64(wh * wh, xx), rhs)) {
        return hi;
    }
    while (hi - lo > 1u) {
        uint64_t mid = lo + (hi - lo) / 2u;
        uint64_t wm = 2u * mid - 1u;
        if (le128(mul64(wm * wm, xx), rhs)) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}

/* Bit k set: phase k has ticks but the step split gives it no step. */
static unsigned empty_phases(uint64_t n, const uint64_t ticks[3])
{
    uint64_t w[3];
    uint64_t parts[3];
    unsigned k, e = 0u;
    w[0] = ticks[0];
    w[1] = 2u * ticks[1];
    w[2] = ticks[2];
    apportion(n, w, parts);
    for (k = 0; k < 3u; k++) {
        if (ticks[k] > 0u && parts[k] == 0u) {
            e |= 1u << k;
        }
    }
    return e;
}

/* The phase durations of tdm_plan_rates, ticks, a cruise that would get no step
 * dropped: 0 or TDM_ERR_TICKS_RANGE (phase in *bad). */
static int rate_phases(uint64_t n, uint64_t v, uint64_t a, uint64_t d, uint64_t f, uint64_t ticks[3], unsigned *bad)
{
    int reaches = le128(mul64(v * v, a + d), mul64(2u * n * a, d));
    if (reaches) {
        ticks[0] = div_round(v * f, a);
        ticks[2] = div_round(v * f, d);
    } else {
        ticks[0] = triangle_phase_ticks(n, a, d, f);
        ticks[2] = triangle_phase_ticks(n, d, a, f);
    }
    ticks[1] = 0u;
    if (ticks[0] > TDM_MAX_T_TICKS) {
        *bad = 0u;
        return TDM_ERR_TICKS_RANGE;
    }
    if (ticks[2] > TDM_MAX_T_TICKS) {
        *bad = 2u;
        return TDM_ERR_TICKS_RANGE;
    }
    if (reaches) {
        /* 2·T_c = 2n·f/v − (T_a + T_d), half up: floor((2n·f − v(T_a + T_d) + v) / 2v). */
        uint64_t plus = 2u * n * f + v;
        uint64_t minus = v * (ticks[0] + ticks[2]);
        ticks[1] = plus <= minus ? 0u : (plus - minus) / (2u * v);
        if (ticks[1] > TDM_MAX_T_TICKS) {
            *bad = 1u;
            return TDM_ERR_TICKS_RANGE;
        }
        if (empty_phases(n, ticks) & 2u) {
            ticks[1] = 0u;
        }
    }
    return 0;
}

int tdm_plan_rates(int32_t steps, uint32_t speed, uint32_t accel, uint32_t decel, uint32_t clock_hz,
                   uint32_t max_rate, tdm_segment out[3], unsigned *count, unsigned *bad_phase)
{
    uint64_t n, v = speed, f = clock_hz;
    uint64_t ticks[3];
    uint32_t t32[3];
    int rc;
    *count = 0u;
    *bad_phase = 0u;
    if (clock_hz == 0u || clock_hz > TDM_PLAN_MAX_CLOCK_HZ || speed == 0u || speed > clock_hz || accel == 0u
        || accel > TDM_PLAN_MAX_ACCEL || decel == 0u || decel > TDM_PLAN_MAX_ACCEL) {
        return TDM_PLAN_E_BAD_LIMIT;
    }
    n = steps < 0 ? (uint64_t)(-(int64_t)steps) : (uint64_t)steps;
    if (n == 0u) {
        return 0;
    }
    if (n > 3u * TDM_MAX_STEPS) {
        return TDM_PLAN_E_TOO_MANY_STEPS;
    }
    rc = rate_phases(n, v, accel, decel, f, ticks, bad_phase);
    if (rc != 0) {
        return rc;
    }
    /* A phase the step split leaves without a step would start the next from rest:
     * a cruise shorter than half a step is dropped (in rate_phases); an empty
     * accelerate or decelerate phase (very unequal rates) is planned again with
     * both rates at the smaller one. */
    if ((empty_phases(n, ticks) & 5u) && accel != decel) {
        uint64_t r = accel < decel ? accel : decel;
        rc = rate_phases(n, v, r, r, f, ticks, bad_phase);
        if (rc != 0) {
            return rc;
        }
    }
    if (n == 1u) {
        /* One step: one segment from rest over the whole time. */
        ticks[0] += ticks[1] + ticks[2];
        ticks[1] = 0u;
        ticks[2] = 0u;
        if (ticks[0] > TDM_MAX_T_TICKS) {
            *bad_phase = 0u;
            return TDM_ERR_TICKS_RANGE;
        }
    }
    t32[0] = (uint32_t)ticks[0];
    t32[1] = (uint32_t)ticks[1];
    t32[2] = (uint32_t)ticks[2];
    return tdm_plan_ticks(steps, t32, max_rate, out, count, bad_phase);
}
