//! The closest approach of every pair of drones, at the samples and between them,
//! found by sorting the drones into cubes at each sample (see the module docs of [`verify`](super) for the
//! bound between samples and the scale).

use super::metric::Metric;
use super::report::ClosestPair;

/// The closest approach under one metric.
pub(super) struct Separation {
    metric: Metric,
    /// Smallest value at a common sample time.
    pub(super) samples_m: f64,
    /// Smallest value of the linearly interpolated motions.
    pub(super) interpolated_m: f64,
    /// Guaranteed lower bound on the true continuous value.
    pub(super) bound_m: f64,
    /// Largest deviation of one drone from its chord within an interval.
    margin_m: f64,
    /// The pair behind the bound, if any pair came within the search radius.
    pub(super) closest: Option<ClosestPair>,
}

/// Drone samples (drones × sample times) from which the sample times are
/// split between threads: a 1,000-drone flight has 3 million, and its check
/// took a fifth of `swarmctl plan`; a bundled mission's few thousand are not
/// worth a thread.
const PARALLEL_FROM_SAMPLES: usize = 1 << 20;

/// Closest approach over all pairs and sample intervals, comparing only drones in
/// neighbouring cubes. Large flights are checked on every core, each thread
/// taking a run of sample times; the runs' results are merged as one pass in
/// time order would have found them (the earlier pair wins a tie).
pub(super) fn separation(
    samples: &[Vec<[f64; 4]>],
    times: &[f64],
    radius_m: f64,
    speed_mps: f64,
    margin_m: f64,
    metric: Metric,
) -> Separation {
    let scale = (radius_m, speed_mps, margin_m, metric);
    let threads = if samples.len().saturating_mul(times.len()) < PARALLEL_FROM_SAMPLES {
        1
    } else {
        std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
    };
    separation_on(samples, times, scale, threads)
}

/// [`separation`] with the sample times split between `threads` threads.
fn separation_on(
    samples: &[Vec<[f64; 4]>],
    times: &[f64],
    scale: (f64, f64, f64, Metric),
    threads: usize,
) -> Separation {
    if threads <= 1 || times.is_empty() {
        return separation_over(samples, times, 0..times.len(), scale);
    }
    let chunk = times.len().div_ceil(threads);
    let run = |from: usize| from..(from + chunk).min(times.len());
    std::thread::scope(|scope| {
        let later: Vec<_> = (chunk..times.len())
            .step_by(chunk)
            .map(|from| scope.spawn(move || separation_over(samples, times, run(from), scale)))
            .collect();
        // The first run here, the later ones merged in time order.
        let first = separation_over(samples, times, run(0), scale);
        later.into_iter().fold(first, |mut out, handle| {
            // A thread's panic is passed on as the same code on this thread would.
            let run = handle
                .join()
                .unwrap_or_else(|e| std::panic::resume_unwind(e));
            out.samples_m = out.samples_m.min(run.samples_m);
            out.interpolated_m = out.interpolated_m.min(run.interpolated_m);
            if run.bound_m < out.bound_m {
                out.bound_m = run.bound_m;
                out.closest = run.closest;
            }
            out
        })
    })
}

/// [`separation`] over the sample times `ks` alone (their intervals to the next
/// sample included).
fn separation_over(
    samples: &[Vec<[f64; 4]>],
    times: &[f64],
    ks: std::ops::Range<usize>,
    (radius_m, speed_mps, margin_m, metric): (f64, f64, f64, Metric),
) -> Separation {
    let mut out = Separation {
        metric,
        samples_m: metric.floor(radius_m),
        interpolated_m: metric.floor(radius_m),
        bound_m: metric.floor(radius_m),
        margin_m,
        closest: None,
    };
    if samples.len() < 2 || times.is_empty() {
        return out;
    }
    let period_s = if times.len() > 1 {
        times[1] - times[0]
    } else {
        0.0
    };
    // Two drones that come within `radius_m` during an interval start it within this.
    let cell_m = (radius_m + 2.0 * speed_mps * period_s).max(1e-9);
    // Each sample time, drones sorted by their cube: the cubes of one column of
    // three (`z − 1 ..= z + 1` under the same `x`, `y`) are one run of the order,
    // and the runs next to successive cubes move only forward (one cursor each).
    let mut cubes: Vec<(u64, u32)> = Vec::with_capacity(samples.len());
    let mut still = vec![false; samples.len()];
    let mut measured = vec![true; samples.len()];
    for k in ks {
        // Two drones holding still were compared at the sample before, in the
        // same cubes, at the same distance with a margin no smaller: nothing new
        // to measure. A pair is measured from a drone that may have moved.
        let repeats = k > 0 && k + 1 < times.len();
        for ((still, measured), s) in still.iter_mut().zip(&mut measured).zip(samples) {
            *still = holds_still(s, k);
            *measured = !(repeats && *still);
        }
        cubes.clear();
        cubes.extend(
            samples
                .iter()
                .enumerate()
                .map(|(i, s)| (cube(&s[k], cell_m), i as u32)),
        );
        cubes.sort_unstable();
        let mut cursors = [0usize; 9];
        let mut start = 0;
        while start < cubes.len() {
            let here = cubes[start].0;
            // Runs are a few drones long: scanning beats bisecting the rest.
            let end = start + run_length(&cubes[start..], |c| c == here);
            let movers = &cubes[start..end];
            start = end;
            if !movers.iter().any(|&(_, i)| measured[i as usize]) {
                continue;
            }
            let [x, y, z] = unpack(here);
            for (cursor, (dx, dy)) in cursors.iter_mut().zip(COLUMN_OFFSETS) {
                let (nx, ny) = (x.wrapping_add_signed(dx), y.wrapping_add_signed(dy));
                let (below, above) = (pack([nx, ny, z - 1]), pack([nx, ny, z + 1]));
                while cubes.get(*cursor).is_some_and(|c| c.0 < below) {
                    *cursor += 1;
                }
                let near = &cubes[*cursor..];
                let near = &near[..run_length(near, |c| c <= above)];
                for &(_, i) in movers {
                    let i = i as usize;
                    if !measured[i] {
                        continue;
                    }
                    for &(_, j) in near {
                        let j = j as usize;
                        // Once per pair: from the lower index when both are measured.
                        if j != i && !(measured[j] && j < i) {
                            let (a, b) = (i.min(j), i.max(j));
                            pair(samples, (a, b), (still[a], still[b]), k, &mut out);
                        }
                    }
                }
            }
        }
    }
    out
}

/// How many of `cubes`, from the first, have a cube satisfying `within`.
fn run_length(cubes: &[(u64, u32)], within: impl Fn(u64) -> bool) -> usize {
    cubes.iter().take_while(|c| within(c.0)).count()
}

/// The nine columns next to a cube's (its own included), in the cubes' order.
const COLUMN_OFFSETS: [(i64, i64); 9] = [
    (-1, -1),
    (-1, 0),
    (-1, 1),
    (0, -1),
    (0, 0),
    (0, 1),
    (1, -1),
    (1, 0),
    (1, 1),
];

/// Bits per coordinate of a packed cube.
const CUBE_BITS: u32 = 21;
/// Cube coordinates are offset by this so negative positions pack, and clamped
/// one short of either end so a neighbour's coordinate never leaves its field
/// (a clamped drone shares its cube with farther ones: compared more, never less).
const CUBE_OFFSET: i64 = 1 << (CUBE_BITS - 1);
const CUBE_MAX: u64 = (1 << CUBE_BITS) - 2;

/// The cube of sample `s` as `x`, `y`, `z` packed high to low: cubes sort by
/// column, then height.
fn cube(s: &[f64; 4], cell_m: f64) -> u64 {
    let coordinate =
        |m: f64| ((m / cell_m).floor() as i64 + CUBE_OFFSET).clamp(1, CUBE_MAX as i64) as u64;
    pack([coordinate(s[1]), coordinate(s[2]), coordinate(s[3])])
}

fn pack([x, y, z]: [u64; 3]) -> u64 {
    (x << (2 * CUBE_BITS)) | (y << CUBE_BITS) | z
}

fn unpack(cube: u64) -> [u64; 3] {
    let field = (1 << CUBE_BITS) - 1;
    [
        cube >> (2 * CUBE_BITS),
        (cube >> CUBE_BITS) & field,
        cube & field,
    ]
}

/// Distance of drones `i` and `j` at sample `k` and over the interval `[k, k + 1]`.
/// `still` says whether each of the two holds still over the interval ([`holds_still`]).
fn pair(
    samples: &[Vec<[f64; 4]>],
    (i, j): (usize, usize),
    still: (bool, bool),
    k: usize,
    out: &mut Separation,
) {
    let (a0, b0) = (&samples[i][k], &samples[j][k]);
    let r0: [f64; 3] = std::array::from_fn(|c| a0[c + 1] - b0[c + 1]);
    let d0 = out.metric.of(r0);
    if d0 < out.samples_m {
        out.samples_m = d0;
    }
    let (mut best, mut best_t) = (d0, a0[0]);
    if let (Some(a1), Some(b1)) = (samples[i].get(k + 1), samples[j].get(k + 1)) {
        // Relative position r(u) = r0 + u (r1 - r0), u in [0, 1].
        let r1: [f64; 3] = std::array::from_fn(|c| a1[c + 1] - b1[c + 1]);
        let dr: [f64; 3] = std::array::from_fn(|c| r1[c] - r0[c]);
        let (d, u) = out.metric.min_on_chord(r0, dr);
        if d < best {
            best = d;
            best_t = a0[0] + u * (a1[0] - a0[0]);
        }
    }
    out.interpolated_m = out.interpolated_m.min(best);
    let margin = |still: bool| if still { 0.0 } else { out.margin_m };
    let deviation_m = margin(still.0) + margin(still.1);
    let bound = best - out.metric.slack(deviation_m);
    if bound < out.bound_m {
        out.bound_m = bound;
        out.closest = Some(ClosestPair {
            first: i,
            second: j,
            time_s: best_t,
        });
    }
}

/// Whether a drone is known not to stray from its chord over `[k, k + 1]`: there
/// is no such interval after its last sample, or it holds still from sample
/// `k − 1` to `k + 2` (else it may stray by `a·Δt²/8`).
fn holds_still(s: &[[f64; 4]], k: usize) -> bool {
    if k + 1 >= s.len() {
        return true; // no interval after the last sample
    }
    let window = &s[k.saturating_sub(1)..(k + 3).min(s.len())];
    window.iter().all(|p| p[1..] == window[0][1..])
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Every pair whose cubes touch, at every sample, no pair skipped: what the
    /// sorted sweep must equal.
    fn every_touching_pair(
        samples: &[Vec<[f64; 4]>],
        times: &[f64],
        (radius_m, speed_mps, margin_m): (f64, f64, f64),
        metric: Metric,
    ) -> Separation {
        let mut out = Separation {
            metric,
            samples_m: metric.floor(radius_m),
            interpolated_m: metric.floor(radius_m),
            bound_m: metric.floor(radius_m),
            margin_m,
            closest: None,
        };
        let period_s = times[1] - times[0];
        let cell_m = radius_m + 2.0 * speed_mps * period_s;
        let cube = |p: &[f64; 4]| -> [i64; 3] {
            std::array::from_fn(|c| (p[c + 1] / cell_m).floor() as i64)
        };
        for k in 0..times.len() {
            for i in 0..samples.len() {
                for j in i + 1..samples.len() {
                    let (a, b) = (cube(&samples[i][k]), cube(&samples[j][k]));
                    if (0..3).all(|c| (a[c] - b[c]).abs() <= 1) {
                        let still = (holds_still(&samples[i], k), holds_still(&samples[j], k));
                        pair(samples, (i, j), still, k, &mut out);
                    }
                }
            }
        }
        out
    }

    /// Drones on a coarse lattice (so some coincide, touch and hold still), on
    /// both sides of the origin, sampled at 10 Hz.
    fn drones() -> impl Strategy<Value = Vec<Vec<[f64; 4]>>> {
        let walk = prop::collection::vec((-2i32..=2, -2i32..=2, -1i32..=1, 0u8..3), 6);
        prop::collection::vec(((-6i32..6, -6i32..6, -3i32..3), walk), 2..12).prop_map(|drones| {
            drones
                .into_iter()
                .map(|(start, walk)| {
                    let mut at = [f64::from(start.0), f64::from(start.1), f64::from(start.2)];
                    let mut samples = Vec::new();
                    for (dx, dy, dz, hold) in walk {
                        for _ in 0..=hold {
                            let t = (samples.len() as f64) * 0.1;
                            samples.push([t, at[0] * 0.3, at[1] * 0.3, at[2] * 0.3]);
                        }
                        at = [
                            at[0] + f64::from(dx),
                            at[1] + f64::from(dy),
                            at[2] + f64::from(dz),
                        ];
                    }
                    samples
                })
                .collect()
        })
    }

    proptest! {
        /// The sweep over sorted cubes, skipping pairs that hold still, finds the
        /// same closest approaches as comparing every pair in touching cubes.
        #[test]
        fn the_sweep_equals_every_touching_pair(
            drones in drones(),
            ellipsoid in any::<bool>(),
        ) {
            // Drones sampled as long as the longest, holding their last position.
            let len = drones.iter().map(Vec::len).max().unwrap_or(0);
            let samples: Vec<Vec<[f64; 4]>> = drones
                .into_iter()
                .map(|mut s| {
                    while s.len() < len {
                        let last = s[s.len() - 1];
                        s.push([s.len() as f64 * 0.1, last[1], last[2], last[3]]);
                    }
                    s
                })
                .collect();
            let times: Vec<f64> = (0..len).map(|k| k as f64 * 0.1).collect();
            prop_assume!(times.len() > 1);
            let metric = if ellipsoid {
                Metric::Cylinder { h: 0.5, v: 0.8 }
            } else {
                Metric::Euclid
            };
            let (radius_m, speed_mps, margin_m) = (0.9, 3.0, 0.01);
            let swept = separation(&samples, &times, radius_m, speed_mps, margin_m, metric);
            let every = every_touching_pair(&samples, &times, (radius_m, speed_mps, margin_m), metric);
            prop_assert_eq!(swept.samples_m, every.samples_m);
            prop_assert_eq!(swept.interpolated_m, every.interpolated_m);
            prop_assert_eq!(swept.bound_m, every.bound_m);
            // Split between threads, the same closest approach, pair and all.
            for threads in [2, 3] {
                let scale = (radius_m, speed_mps, margin_m, metric);
                let split = separation_on(&samples, &times, scale, threads);
                prop_assert_eq!(split.samples_m, swept.samples_m);
                prop_assert_eq!(split.interpolated_m, swept.interpolated_m);
                prop_assert_eq!(split.bound_m, swept.bound_m);
                prop_assert_eq!(&split.closest, &swept.closest);
            }
        }
    }
}
