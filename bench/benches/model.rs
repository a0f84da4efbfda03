//! Reference-model throughput: periods per second of the integer model (the
//! hardware algorithm) and of the exact f64 kinematics, on the paper's experiment.
//! Run: `cargo bench -p tdm-stepper-bench --bench model`.

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use tdm_stepper::model::{exact, SegmentPlan};
use tdm_stepper::vectors::paper_experiment_segments;

fn model(c: &mut Criterion) {
    let axes = paper_experiment_segments();
    let steps: u64 = axes.iter().flatten().map(|s| s.n_steps() as u64).sum();
    let mut g = c.benchmark_group("paper_experiment");
    g.throughput(Throughput::Elements(steps));
    g.bench_function("integer_model_periods", |b| {
        b.iter(|| {
            let mut sum = 0u64;
            for seg in axes.iter().flatten() {
                sum += SegmentPlan::new(*black_box(seg)).periods().map(u64::from).sum::<u64>();
            }
            sum
        })
    });
    g.bench_function("exact_f64_times", |b| {
        b.iter(|| axes.iter().flatten().map(|s| exact::step_times(black_box(s)).len()).sum::<usize>())
    });
    g.finish();
}

criterion_group!(benches, model);
criterion_main!(benches);
