/* tdm_scurve.h: the S-curve planner of the tdm-stepper IP core (portable C99, no
 * heap, about 5 KB of stack). It plans a jerk-limited (seven-phase) or a fourth-order
 * (snap-limited) move into polynomial segments exactly as the Rust planner
 * (tdm_stepper::model::scurve) does: the same segments for the same inputs. The
 * profile is computed in double with +, -, *, / and sqrt only (each correctly rounded
 * by IEEE 754), so build it without floating-point contraction (GCC:
 * -ffp-contract=off; a Cortex-M4's soft double never contracts).
 *
 * Return values: 0 with *count segments in out[0..*count); 1..6, the segment error
 * code the core would report, for segment *count; or a negative TDM_SCURVE_E_* code. */
#ifndef TDM_SCURVE_H
#define TDM_SCURVE_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* One polynomial segment: start and end speed (Q0.32 steps per tick), A = a0.T^2/2
 * in Q32 steps, duration T (ticks, 1..2^24) and signed steps. */
typedef struct {
    uint32_t v0_rate;
    uint32_t v1_rate;
    int64_t a_q32;
    uint32_t t_ticks;
    int32_t steps;
} tdm_poly_segment;

#define TDM_SCURVE_MAX_SEGMENTS 128 /* the most segments one move plans into */

#define TDM_SCURVE_E_BAD_LIMIT (-21) /* a limit or speed that is not a positive finite number, or a speed above v_max */
#define TDM_SCURVE_E_TOO_SHORT (-24) /* the move is shorter than its speed change needs */
#define TDM_SCURVE_E_TOO_SLOW (-25)  /* more than 2^24 ticks without a step: raise the jerk or the speed */
#define TDM_SCURVE_E_TOO_MANY (-26)  /* more than TDM_SCURVE_MAX_SEGMENTS segments: plan several moves */

/* Checks one polynomial segment as the core does at push: 0 or its code (1..6).
 * max_rate is the core's RMAX (ID_MAX_RATE). */
int tdm_poly_check(const tdm_poly_segment *seg, uint32_t max_rate);

/* A jerk-limited move: steps (signed) from v_start to v_end (steps/s, 0..v_max), top
 * speed v_max, acceleration a_max with jerk j_max, deceleration d_max with jerk
 * jd_max (steps/s^2, steps/s^3), at clock_hz. out holds TDM_SCURVE_MAX_SEGMENTS. */
int tdm_plan_jerk(int32_t steps, double v_start, double v_end, double v_max, double a_max, double j_max,
                  double d_max, double jd_max, uint32_t clock_hz, uint32_t max_rate, tdm_poly_segment *out,
                  unsigned *count);

/* The fourth-order (snap-limited) profile, rest to rest: steps (signed), v_max, a_max,
 * j_max and s_max (steps/s^4), the same for speeding up and slowing down. */
int tdm_plan_fourth(int32_t steps, double v_max, double a_max, double j_max, double s_max, uint32_t clock_hz,
                    uint32_t max_rate, tdm_poly_segment *out, unsigned *count);

#ifdef __cplusplus
}
#endif

#endif /* TDM_SCURVE_H */
