//! Criterion benchmarks: dieface against curvo on the same fixtures, row by row.
//!
//! `cargo bench -p dieface-bench` (filter with e.g. `cargo bench -p dieface-bench -- surface_d1`).
//! Each row is a criterion group with the two functions `dieface` and `curvo`; an
//! evaluation row's iteration evaluates all sample parameters once (see
//! `Row::ops`, the throughput is reported per evaluation), a tessellation row's iteration
//! tessellates the whole surface once at 0.01 mm.

use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion, SamplingMode, Throughput};
use dieface_bench::{eval_rows, tessellation_rows, Fixtures};

fn kernel(c: &mut Criterion) {
    let fx = Fixtures::new();
    let mut rows = eval_rows(&fx);
    rows.extend(tessellation_rows(&fx, false, false));
    for row in &rows {
        let mut g = c.benchmark_group(&row.id);
        if let Some(m) = &row.mesh {
            eprintln!(
                "{}: dieface {} triangles, max deviation {:.4} mm; curvo ({}) {} triangles, max deviation {:.4} mm",
                row.id, m.ours_triangles, m.ours_deviation, m.theirs_settings, m.theirs_triangles, m.theirs_deviation
            );
            g.sample_size(10)
                .sampling_mode(SamplingMode::Flat)
                .warm_up_time(Duration::from_secs(1))
                .measurement_time(Duration::from_secs(5));
        } else {
            g.throughput(Throughput::Elements(row.ops as u64))
                .warm_up_time(Duration::from_millis(500))
                .measurement_time(Duration::from_secs(2));
        }
        g.bench_function("dieface", |b| b.iter(|| (row.ours)()));
        g.bench_function("curvo", |b| b.iter(|| (row.theirs)()));
        g.finish();
    }
}

criterion_group!(benches, kernel);
criterion_main!(benches);
