#!/usr/bin/env bash
# Mutation checks: each line below breaks the design in one place on purpose, and the
# named test must then fail. A mutant that survives means the tests do not hold that
# behaviour. Runs in a scratch git worktree (the repository tree is not touched), one
# mutant at a time; takes about 3 to 5 minutes per mutant on a 2-core machine.
#
#   scripts/mutants.sh            # all mutants
#   scripts/mutants.sh 3 7        # only mutants 3 and 7
#
# Exit status: 0 when every mutant was killed, 1 when one survived or did not apply.
set -uo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
work="${MUTANTS_WORK:-$(mktemp -d /tmp/tdm-mutants.XXXXXX)}"
export CARGO_TARGET_DIR="${MUTANTS_TARGET:-$repo/target/mutants}"

# Not listed: the fallback threshold P' + T' instead of P' + 2T'. It differs only when
# P' lies within 2T' = 32·T of 2^64. P' = 8T·(n·2^32 − d)/d with d = |D·2^32| ≡ ±n·2^32
# (mod T), so P' moves in steps far wider than 32·T as d, T or n change by one, and a
# segment lands in that window only by a coincidence the boundary search in
# tests/hdl_core_setup.rs does not find (its closest segments on either side are the
# test's `fallback_boundary`): equivalent in practice.
#
# Mutant 15 (the uniform step misses a carry when the running remainder is exactly
# 2n) needs a segment on the uniform path with n even and T ≡ n/2 (mod n); an exactly
# uniform one cannot have that (v0 would be 2^33 / odd), so hdl_core's
# uniform_step_carries_a_remainder_equal_to_2n uses a nearly uniform one (v0 =
# (2^33 − 1)/161, T = 161n/2, n = 3.4 M) whose P' passes the root's width.
#
# Mutant 24 (K = 1 on the registered kind) passes hdl_core's K = 1 run of the paper's
# experiment; hdl_core_setup's short segments, which end with room in the FIFO, kill it.
#
# id # file # perl -0pe substitution # test binary # test name filter # what it breaks
mutants=(
  "1#ip/src/hdl/core.rs#s/<< 41\)\n(\s*)\+ bit_cast::<DIV_NUM_BITS, 64>\(self.s_d.q.val\(\)\)/<< 41)\n\1+ 0/#hdl_core_setup#setup_state_equals#B' floored instead of rounded"
  "2#ip/src/hdl/core.rs#s/self.p_wide.d.next = \(self.div.quotient.val\(\).get_bits::<40>\(64\) != 0\) \| /self.p_wide.d.next = /#hdl_core_setup#setup_state_equals#fallback test ignores the quotient's high half (P' ≥ 2^64 takes the root)"
  "3#ip/src/hdl/pulse_stage.rs#s/self.half1.d.next = self.d17.val\(\).get_bits::<16>\(1\);/self.half1.d.next = self.d17.val().get_bits::<16>(2);/#hdl_pulse_stage#high_time_equals_the_model#STEP pulse a quarter period"
  "4#ip/src/hdl/step_gen.rs#s/\(self.count.q.val\(\) == 2\)/(self.count.q.val() == 3)/#hdl_step_gen#short_segments_both_axes#every edge one tick early"
  "5#ip/src/hdl/step_gen.rs#s/self.under.d.next = true;/self.under.d.next = false;/#hdl_step_gen#starved_fifo_flags_underrun#underrun never flagged"
  "6#ip/src/hdl/step_gen.rs#s/if self.abort.val\(\) \{/if self.abort.val() & self.reset.val() {/#system#interrupts_random_traffic_and_abort#abort ignored by the step generators"
  "7#ip/src/hdl/exmc.rs#s/if !self.nwe2.q.val\(\) & !self.nwe3.q.val\(\) & !self.ne2.q.val\(\) & !self.ne3.q.val\(\) \{/if !self.nwe2.q.val() & !self.ne2.q.val() {/#system#bad_input_through_the_bus#bus write captured on a single sample"
  "8#ip/src/hdl/root.rs#s/self.trial_out.next = bit_cast::<TRIAL_BITS, PAIR_BITS>\(self.t_w.val\(\) \+ \(self.m_w.val\(\) >> 2\)\);/self.trial_out.next = bit_cast::<TRIAL_BITS, PAIR_BITS>(self.t_w.val() + (self.m_w.val() >> 3));/#hdl_root#root_two_digits#root pair: wrong trial step after digits 01"
  "9#ip/src/hdl/root.rs#s/self.d3.next = self.rem4.val\(\) - self.t3_w.val\(\);/self.d3.next = self.rem4.val() - bit_cast::<PAIR_BITS, TRIAL_BITS>(self.tlo_in.val());/#hdl_root#root_two_digits#root pair: wrong threshold for digits 11"
  "10#ip/src/hdl/push_check.rs#s/self.rcode.d.next = 5.into\(\);/self.rcode.d.next = 4.into();/#hdl_push_check#verdicts_equal_the_model#range check reports the wrong code (steps range as T range)"
  "11#ip/src/hdl/core.rs#s/self.s_eprev.d.next = self.w_e.q.val\(\);\n(\s*)self.w_e.d.next = self.e_next.val\(\);\n(\s*)self.w_i.d.next = self.i_next.val\(\);\n(\s*)if self.last/self.s_eprev.d.next = self.w_e.q.val() + 1;\n\1self.w_e.d.next = self.e_next.val();\n\2self.w_i.d.next = self.i_next.val();\n\3if self.last/#hdl_core#two_axes_match#square-root period entry one tick short"
  "12#ip/src/hdl/core.rs#s/self.pe_last.d.next = true;/self.pe_last.d.next = false;/#hdl_core#two_axes_match#dwell entry without its last flag"
  "13#ip/src/hdl/core.rs#s/& \(\(self.pk_kind.val\(\) == 0\) \| self.pk_sat.val\(\)\)/\& (self.pk_kind.val() == 0)/#hdl_core#setups_ahead_of_time#no setup ahead of time"
  "14#ip/src/hdl/divider.rs#s/self.num_out.next = \(self.num_in.val\(\) << 2\) \| 3;/self.num_out.next = (self.num_in.val() << 2) | 2;/#hdl_divider#divider_radix_4#divider pair: digit 3 written as 2"
  "15#ip/src/hdl/core.rs#s/if !self.u_r2.q.val\(\).get_bit\(33\) \{/if !self.u_r2.q.val().get_bit(33) \& (self.u_r2.q.val() != 0) {/#hdl_core#uniform_step_carries#uniform step: remainder equal to 2n not carried"
  "16#ip/src/hdl/core.rs#s/if self.p_ready.q.val\(\) \{/if self.div.valid.val() {/#hdl_core_setup#setup_state_equals#fallback decided on the registered test a cycle early (the quotient before the last digits)"
  "17#ip/src/hdl/root.rs#s/self.t3_w.val\(\) - \(\(self.m_w.val\(\) >> 2\) \| \(self.m_w.val\(\) >> 3\)\)/self.t3_w.val() - (self.m_w.val() >> 2)/#hdl_root#root_two_digits#root pair: next 3t + 3m/2 after digits 01 off by m/8"
  "18#ip/src/hdl/step_gen.rs#s/\n\s*\| \(\(self.fifo.level.val\(\) == self.depth_less.val\(\)\) & self.push.val\(\) & !self.gen.pop.val\(\)\);/;/#hdl_step_gen#full_flag_follows#registered full flag misses a push that fills the FIFO"
  "19#ip/src/hdl/core.rs#s/self.s_nz.d.next = self.w_n.q.val\(\) == 0;/self.s_nz.d.next = false;/#hdl_core#two_axes_match#registered steps = 0 flag never set (a dwell set up as a move)"
  "20#ip/src/hdl/core.rs#s/self.w_slot.d.next = self.pk_slot.val\(\);/self.w_slot.d.next = self.slot_nm.val();/#hdl_core#two_axes_match#context written into the slot of axis m + 1's parity"
  "21#ip/src/hdl/regfile.rs#s/self.pushed\[i\].q.val\(\) - self.m_taken\[i\].q.val\(\) - 1;/self.pushed[i].q.val() - self.m_taken[i].q.val();/#hdl_regfile#commands_pass#LEVEL counts a rejected push a cycle longer"
  "22#ip/src/hdl/regfile.rs#s/self.ql_valid.d.next = self.st_valid.val\(\) & self.accepting.val\(\) & \(self.s_taken.val\(\) != self.o_taken.val\(\)\);/self.ql_valid.d.next = self.st_valid.val() & self.accepting.val();/#system#interrupts_random_traffic#QLOW raised by every status word of a low queue, not only when a segment was taken"
  "23#ip/src/hdl/top.rs#s/self.core.cmd_v0.next = self.c_word.q.val\(\).get_bits::<32>\(0\);/self.core.cmd_v0.next = self.cmd_fifo.data_out.val().get_bits::<32>(0);/#system#paper_experiment#a push's v0 taken from the FIFO a cycle after it left (the command stage skipped for one field)"
  "24#ip/src/hdl/core.rs#s/self.pk_kind.next = self.nx_kind.val\(\);/self.pk_kind.next = self.pf_kind.q.val();/#hdl_core_setup#setup_state_equals#K = 1 decides on the registered kind, a cycle old after its own commit"
  "25#ip/src/hdl/step_gen.rs#s/self.pos_delta.next = self.c_minus_one.val\(\);/self.pos_delta.next = 1.into();/#hdl_step_gen#short_segments_both_axes#the position counts a step backwards as one forwards"
  "26#ip/src/hdl/seg_queue.rs#s/self.rd\[i\].d.next = self.wr\[i\].q.val\(\);/self.rd[i].d.next = self.rd[i].q.val();/#hdl_seg_queue#seg_queue_three_ways#abort leaves the segment queues as they were"
  "27#ip/src/hdl/seg_queue.rs#s/if self.abort.val\(\) \{\n\s*self.wr\[i\].d.next = self.wr\[i\].q.val\(\);\n/if self.abort.val() {\n/#hdl_seg_queue#seg_queue_three_ways#a push in the abort's cycle survives the flush"
  "28#ip/src/hdl/axis_bank.rs#s/\n\s*\| \(self.pulse.p1_valid.val\(\) & \(self.pulse.p1_axis.val\(\).index\(\) == i\)\);/;/#hdl_axis_bank#axes_released_together#an entry in the pulse stage's last register not counted as coming (a starved axis ends its move with an entry on the way)"
  "29#ip/src/hdl/axis_bank.rs#s/self.sat_bus\[i\].value.next = self.axes\[i\].full.val\(\) \| !self.pend_pick\[i\].value.val\(\);/self.sat_bus[i].value.next = self.axes[i].full.val();/#hdl_axis_bank#axes_released_together#an axis with nothing to compute never counts as satisfied (no setup ahead of time)"
  "30#ip/src/hdl/exmc.rs#s/self.captured.d.val\(\) & \(self.nwe1.q.val\(\) \| self.ne1.q.val\(\)\)/self.captured.d.val() \& (self.nwe2.q.val() | self.ne2.q.val())/#hdl_exmc#commits_reads#wr_next from this cycle's strobes, not the next cycle's"
  "31#ip/src/hdl/regfile.rs#s/self.rd_axis_next.val\(\).get_bit\(4\) & \(self.rn_axis.val\(\).index\(\) == i\)/(self.rn_axis.val().index() == i)/#hdl_regfile#commands_pass#a global register's read also selects the axis its address bits 7..4 name"
  "32#ip/src/hdl/regfile.rs#s/self.st_aq.d.next = self.wr_axis_next.val\(\);/self.st_aq.d.next = self.rn_axis.val();/#hdl_regfile#commands_pass#a push reads the staging memories at the read address, not its own axis"
  "33#ip/src/hdl/regfile.rs#s/self.fifo_full.next = self.cmd_full.val\(\) \| \(self.cmd_almost_full.val\(\) & self.chk.out_valid.val\(\)\);/self.fifo_full.next = self.cmd_full.val();/#hdl_regfile#commands_pass#a command taken while the one before it enters a command FIFO with one slot left (lost 4 cycles later)"
  "34#ip/src/hdl/cdc.rs#s/self.afull.d.next = self.level_w.val\(\) >= 3;/self.afull.d.next = self.level_w.val() >= 4;/#hdl_cdc_fifo#async_fifo_flags#almost_full only when full"
  "35#ip/src/hdl/seg_queue.rs#s/\(\(\(self.wr\[i\].q.val\(\) \+ 1\) \^/(((self.wr[i].q.val()) ^/#hdl_seg_queue#seg_queue_three_ways#a queue's full flag tested on its level before the push (never set: a full queue overwritten)"
  "36#ip/src/hdl/seg_queue.rs#s/self.rd\[i\].d.next = self.rd\[i\].q.val\(\) \+ 1;\n\s*self.full\[i\].d.next = false;/self.rd[i].d.next = self.rd[i].q.val() + 1;/#hdl_seg_queue#seg_queue_three_ways#a pop leaves a full queue's full flag set (pushes refused with room)"
  "37#ip/src/hdl/core.rs#s/\(bit_cast::<37, 32>\(self.w_t.q.val\(\)\) << 4\) \| 8;/(bit_cast::<37, 32>(self.w_t.q.val()) << 4) | 7;/#hdl_core#two_axes_match#decelerating E rounded with 7 for 8 (T − E one tick off where τ' + 8 is a multiple of 16)"
  "38#ip/src/hdl/push_check.rs#s/\(self.x_steps.val\(\) < self.c_min_n.val\(\)\)/(self.x_steps.val() < self.c_max_n.val())/#hdl_push_check#verdicts_equal_the_model#a negative step count never found out of range (the compare below −MAX_STEPS against +MAX_STEPS)"
  "39#ip/src/hdl/seg_queue.rs#s/self.ne\[i\].d.next = \(\(\(self.rd\[i\].q.val\(\) \+ 1\) \^ self.wr\[i\].q.val\(\)\) & self.c_wrap.val\(\)\) != 0;/self.ne[i].d.next = true;/#hdl_seg_queue#seg_queue_three_ways#a pop that empties a queue leaves its nonempty flag set"
  "40#ip/src/hdl/seg_queue.rs#s/\{\n\s*self.ne\[i\].d.next = true;\n\s*\}/{\n            }/#hdl_seg_queue#seg_queue_three_ways#a push does not set its queue's nonempty flag"
  "41#ip/src/hdl/regfile.rs#s/self.rd_data.next = self.g_data.val\(\);/self.rd_data.next = self.a_data.val();/#hdl_regfile#commands_pass#a global register reads as the read axis's value (0)"
  "42#ip/src/hdl/ram_fifo.rs#s/self.count_delta.next = self.minus_one.val\(\);/self.count_delta.next = 1.into();/#hdl_step_gen#full_flag_follows#the period FIFO counts a pop as a push"
  "43#ip/src/hdl/core.rs#s/self.nn.next = 0.into\(\);/self.nn.next = self.nm.q.val() + 1;/#hdl_core#t_calc_is_what_the_constant_says#axis m + 2 never wraps to 0 (the registered next axis runs past the last)"
  "44#ip/src/hdl/step_gen.rs#s/self.one.d.next = self.head.val\(\).get_bit\(51\);/self.one.d.next = false;/#hdl_step_gen#one_tick_entries#a one-tick entry loaded without its flag (it runs 2^32 ticks)"
  "45#ip/src/hdl/input_filter.rs#s/\(self.count.q.val\(\) >= self.samples.val\(\)\);/(self.count.q.val() > self.samples.val());/#hdl_machine_io#input_filter_equals#the filter takes one sample more than n + 1"
  "46#ip/src/hdl/machine_io.rs#s/self.latched.d.next = \(self.estop_f.active.val\(\) & self.c_groups.val\(\).get_bit\(0\)\) \| /self.latched.d.next = /#hdl_machine_io#estop_starts_latched#a re-arm clears the e-stop latch while the e-stop is still active"
  "47#ip/src/hdl/machine_io.rs#s/\(self.wd_timeout.val\(\) == 0\) \| self.wd_feed.val\(\) \| /(self.wd_timeout.val() == 0) | /#hdl_machine_io#the_watchdog_trips#a feed does not restart the watchdog"
  "48#ip/src/hdl/machine_io.rs#s/if self.edges.val\(\).get_bit\(0\) \{/if self.edges.val().get_bit(1) {/#hdl_machine_io#latch_strobes_follow#the home latch follows the probe's edge choice"
  "49#ip/src/hdl/top.rs#s/self.core.abort.next = self.c_abort.q.val\(\) \| \(self.\\\$io.hard_stop.val\(\) & !self.c_push.q.val\(\)\);/self.core.abort.next = self.c_abort.q.val();/#system#estop_through_the_bus#the machine I/O's hard stop does not reach the core"
  "50#ip/src/hdl/top.rs#s/\(self.\\\$io.hard_stop.val\(\) & !self.c_push.q.val\(\)\)/self.\\\$io.hard_stop.val()/#system#estop_through_the_bus#the hard stop's abort meets a push in the same cycle (the push is dropped uncounted)"
  "51#ip/src/hdl/axis_bank.rs#s/if self.probe_latch.val\(\) \{/if self.hl_pick[i].value.val() {/#hdl_axis_bank#axes_released_together#the probe latches take the position on the axis's home strobe"
  "52#ip/src/hdl/io_regs.rs#s/\(self.l_hbits.val\(\) \^ self.htog_b.q.val\(\)\) & self.l_onehot.val\(\)/self.l_hbits.val() ^ self.htog_b.q.val()/#system#home_and_probe_latch#a latch word's home toggle is compared with every axis's (home events on axes that did not latch)"
  "53#ip/src/hdl/core.rs#s/self.queues.flush.next = self.axis_flush.val\(\) \| /self.queues.flush.next = /#hdl_core#one_axis_stops#the per-axis stop leaves the axis's queue (its segments run after the stop)"
  "54#ip/src/hdl/machine_io.rs#s/self.limit_v.next = self.toward_v.val\(\) & self.toward_q.q.val\(\);/self.limit_v.next = self.toward_v.val();/#system#a_limit_in_the_direction#a limit stops an axis on one tick of DIR toward it (a move away from an active limit is stopped at its start)"
  "55#ip/src/hdl/push_guard.rs#s/ & \(self.st_taken.val\(\) == self.st_pushed.val\(\)\);/;/#hdl_machine_io#push_guard#the plan is taken from a status word of an axis with pushes the core has not taken"
  "56#ip/src/hdl/push_guard.rs#s/\(self.u_sum.val\(\) > self.u_max.val\(\)\)/(self.u_sum.val() >= self.u_max.val())/#system#soft_limits#the soft maximum is exclusive (a push ending on it is rejected)"
  "57#ip/src/hdl/step_gen.rs#s/self.more.val\(\) \| !self.fifo.empty.val\(\) \| /self.more.val() | /#hdl_axis_bank#axes_released_together#BUSY leaves out periods waiting in the FIFO for START"
  "58#ip/src/hdl/core.rs#s/self.op_b.d.next = self.narrow.val\(\).get_bits::<32>\(0\) << 1;/self.op_b.d.next = self.narrow.val().get_bits::<32>(0);/#hdl_core#controlled_stop#the stop ramp's T is n(Δ + 1), not 2n(Δ + 1)"
  "59#ip/src/hdl/stop_ramp.rs#s/self.d1.next = self.r_delta.val\(\) \+ 1;/self.d1.next = self.r_delta.val();/#hdl_core#controlled_stop#the ramp's v0 from Δ instead of Δ + 1"
  "60#ip/src/hdl/core.rs#s/& !self.bank.moving.val\(\) & self.c_cs.val\(\)/\& !self.bank.active.val() \& self.c_cs.val()/#hdl_core#controlled_stop#a stop in a dwell forms a ramp"
  "61#ip/src/hdl/stop_regs.rs#s/self.enable.val\(\) \| \(self.staged.val\(\) < self.c_min.val\(\)\)/self.enable.val()/#system#controlled_stop#STOP_DECEL below the minimum is taken"
  "62#ip/src/hdl/core.rs#s/self.axis_drop.next = true;/self.axis_drop.next = false;/#hdl_core#controlled_stop#a segment pushed during a ramp that a held request keeps runs after it"
  "63#ip/src/hdl/stop_ramp.rs#s/self.stopping.next = self.r_next.q.val\(\) \| self.r_cur.q.val\(\);/self.stopping.next = 0.into();/#hdl_core#controlled_stop#a held request cuts its own ramp again"
  "64#ip/src/hdl/machine_io.rs#s/\| \(self.tripped.q.val\(\) & !self.stop_mode.val\(\).get_bit\(2\)\)/| self.tripped.q.val()/#hdl_machine_io#stop_modes#a controlled watchdog trip stops hard at once"
  "65#ip/src/hdl/stop_regs.rs#s/self.home_sync.sig_in.next = self.home_r.q.val\(\);/self.home_sync.sig_in.next = 0.into();/#system#stop_modes#STOP_HOME never reaches clk"
  "66#ip/src/hdl/top.rs#s/self.stop_regs.cstop.val\(\) \| self.\\\$io.axis_cstop.val\(\)/self.stop_regs.cstop.val()/#system#stop_modes#the sources in controlled mode never reach the core"
  "67#ip/src/hdl/stop_ramp.rs#s/c_bypass: Constant::new\(K == 1\),/c_bypass: Constant::new(false),/#hdl_core#controlled_stop_ramps_down_on_a_one_axis_core#K = 1 reads the last period before its registered write reaches the RAM"
  "68#ip/src/hdl/io_regs.rs#s/self.c_one.val\(\) << self.rd_axis_next.val\(\).get_bits::<4>\(0\)/self.c_one.val()/#system#io_axis_reads#IO_AXIS of every axis reads axis 0's inputs"
  "69#ip/src/hdl/poly_check.rs#s/self.fast_rate.q.val\(\) \| self.big1.q.val\(\) \| self.big2.val\(\)/self.fast_rate.q.val() | self.big1.q.val()/#hdl_push_check#poly::verdicts_equal_the_model#the polynomial check misses a second control point above the hull"
  "70#ip/src/hdl/poly_check.rs#s/\(self.pv1.val\(\) << 1\) \+ self.pv1.val\(\)/(self.pv1.val() << 1)/#hdl_push_check#poly::verdicts_equal_the_model#β2 takes 2·v1·T for 3·v1·T"
  "71#ip/src/hdl/poly_setup.rs#s/self.k_c.d.next = \(self.n32.val\(\) << 2\)/self.k_c.d.next = (self.n32.val() << 1)/#hdl_poly#poly_setup_equals#C' takes 2n·2^32 for 4n·2^32"
  "72#ip/src/hdl/poly_setup.rs#s/self.xs.next = bit_cast::<ACC, X>\(self.x.q.val\(\)\) \| self.fill_acc.val\(\);/self.xs.next = bit_cast::<ACC, X>(self.x.q.val());/#hdl_poly#poly_setup_equals#a negative multiplicand not sign-extended"
  "73#ip/src/hdl/poly_unit.rs#s/self.srch.in_base.next = 1.into\(\);/self.srch.in_base.next = 0.into();/#hdl_poly#poly_unit_gives#the first step searched from tick 0 instead of the setup's base 1"
  "74#ip/src/hdl/poly_unit.rs#s/self.srch.out_w1.val\(\) - self.s_wide.val\(\);/self.srch.out_w1.val();/#hdl_poly#poly_unit_gives#the stored remainder misses the next step's S"
  "75#ip/src/hdl/poly_unit.rs#s/if self.d.val\(\).get_bit\(2\) \{\n(\s*)self.dig.next = 2.into\(\);/if self.d.val().get_bit(2) {\n\1self.dig.next = 1.into();/#hdl_poly#poly_unit_gives#the next start digit one low after periods of 4 to 7 ticks (same edges, more cycles)"
)

only=("$@")
git -C "$repo" worktree add --detach "$work/tree" HEAD >/dev/null 2>&1 || { echo "cannot make a worktree in $work"; exit 1; }
trap 'git -C "$repo" worktree remove --force "$work/tree" >/dev/null 2>&1' EXIT
tree="$work/tree"
status=0
for m in "${mutants[@]}"; do
  IFS='#' read -r id file subst test filter what <<<"$m"
  if [ ${#only[@]} -gt 0 ] && [[ ! " ${only[*]} " == *" $id "* ]]; then continue; fi
  git -C "$tree" checkout -q -- .
  before=$(sha1sum "$tree/$file")
  perl -0pi -e "$subst" "$tree/$file"
  if [ "$before" = "$(sha1sum "$tree/$file")" ]; then
    echo "mutant $id ($what): DID NOT APPLY to $file"
    status=1
    continue
  fi
  start=$(date +%s)
  if (cd "$tree" && cargo test --release -q --test "$test" "$filter" >"$work/mutant-$id.log" 2>&1); then
    echo "mutant $id ($what): SURVIVED $test::$filter ($(( $(date +%s) - start )) s, log $work/mutant-$id.log)"
    status=1
  else
    if grep -q "test result: FAILED\|panicked" "$work/mutant-$id.log"; then
      echo "mutant $id ($what): killed by $test::$filter ($(( $(date +%s) - start )) s)"
    else
      echo "mutant $id ($what): build failed, see $work/mutant-$id.log"
      status=1
    fi
  fi
done
git -C "$tree" checkout -q -- .
exit $status
