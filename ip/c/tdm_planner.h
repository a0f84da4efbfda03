/* tdm_planner.h: the move planner of the tdm-stepper IP core (portable C99,
 * integer-only, no heap). It turns a rest-to-rest move into at most three segments
 * {v0_rate, t_ticks, steps} the core accepts, exactly as the Rust planner
 * (tdm_stepper::model::planner) does: the same segments for the same inputs.
 *
 * Return values: 0 with *count segments in out[0..*count); 1..6, the segment error
 * code the core would report, for the phase in *bad_phase (0 accelerate, 1 cruise,
 * 2 decelerate); or a negative TDM_PLAN_E_* code. */
#ifndef TDM_PLANNER_H
#define TDM_PLANNER_H

#include <stdint.h>
#include "tdm_driver.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TDM_PLAN_E_NO_DURATION (-20)    /* every phase is 0 ticks long */
#define TDM_PLAN_E_BAD_LIMIT (-21)      /* a speed, rate or clock that is 0 or out of range */
#define TDM_PLAN_E_TOO_MANY_STEPS (-22) /* a phase would carry more than 2^24 steps */

/* Largest acceleration or deceleration, steps/s^2, and clock, Hz, tdm_plan_rates takes. */
#define TDM_PLAN_MAX_ACCEL 0x7FFFFFFFul
#define TDM_PLAN_MAX_CLOCK_HZ (1ul << 29)

/* The paper's form: phase durations in clk ticks (accelerate, cruise, decelerate).
 * Steps are split over the phases in proportion to their area (largest remainder),
 * each v0 is the previous segment's end speed rounded to the rate unit (lowered
 * where needed so no segment reverses). 0 steps: one dwell per non-empty phase.
 * max_rate is the core's RMAX (ID_MAX_RATE, tdm_dev.max_rate). */
int tdm_plan_ticks(int32_t steps, const uint32_t phase_ticks[3], uint32_t max_rate,
                   tdm_segment out[3], unsigned *count, unsigned *bad_phase);

/* A move as distance (signed steps), top speed (steps/s), acceleration and
 * deceleration (steps/s^2), clock in Hz. Reaches the speed when v^2(a + d) <= 2n.a.d:
 * phases round(v.f/a), round(n.f/v - (T_a + T_d)/2), round(v.f/d) ticks; else a
 * triangle, T_a = round(f.sqrt(2n.d / (a(a + d)))) and T_d likewise. A phase the
 * step split would leave without a step is not left as a dwell: a cruise shorter
 * than half a step is dropped, and an empty accelerate or decelerate phase (a short
 * move with very unequal rates) makes it plan again with both rates at the smaller
 * one. One step is one segment from rest; 0 steps gives no segment (*count = 0). */
int tdm_plan_rates(int32_t steps, uint32_t speed, uint32_t accel, uint32_t decel, uint32_t clock_hz,
                   uint32_t max_rate, tdm_segment out[3], unsigned *count, unsigned *bad_phase);

#ifdef __cplusplus
}
#endif

#endif /* TDM_PLANNER_H */
