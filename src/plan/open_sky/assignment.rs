//! Goals for interchangeable drones such that no exchange of two drones' goals,
//! and no move of one drone to a goal nobody takes, lowers the summed squared
//! distances: the property of CAPT's assignment (Turpin, Michael & Kumar, IJRR
//! 2014) that its straight lines need (see the proof in `open_sky`).
//!
//! The least-sum assignment itself (a dense assignment problem, cubic in the
//! drones) has it, but so does any local optimum of exchanges, which is what is
//! searched here: a first assignment by recursive bisection (drones and goals
//! split at the median of the axis they spread most along, in proportion), then
//! exchanges until none helps. Each exchange lowers an integer sum by at least
//! 2, so the search ends; a pass over all pairs of 5,000 drones takes tens of
//! milliseconds.

use std::time::Instant;

/// A voxel's coordinates.
pub(super) type Point = [i32; 3];

/// For each drone at `starts` (in order) the index of its goal in `goals`, all
/// distinct, stable under exchanges (see the module docs); `None` if there are
/// fewer goals than drones or `until` passes first.
pub(in crate::plan) fn pairwise_stable(
    starts: &[Point],
    goals: &[Point],
    until: Instant,
) -> Option<Vec<usize>> {
    if goals.len() < starts.len() {
        return None;
    }
    let mut goal_of = vec![usize::MAX; starts.len()];
    let mut drones: Vec<usize> = (0..starts.len()).collect();
    let mut goal_ids: Vec<usize> = (0..goals.len()).collect();
    bisect(&mut drones, &mut goal_ids, (starts, goals), &mut goal_of);
    let mut taken = vec![false; goals.len()];
    for &g in &goal_of {
        taken[g] = true;
    }
    let mut unused: Vec<usize> = (0..goals.len()).filter(|&g| !taken[g]).collect();
    loop {
        let mut improved = false;
        for i in 0..starts.len() {
            if Instant::now() >= until {
                return None;
            }
            for j in i + 1..starts.len() {
                if dot(
                    sub(starts[i], starts[j]),
                    sub(goals[goal_of[i]], goals[goal_of[j]]),
                ) < 0
                {
                    goal_of.swap(i, j);
                    improved = true;
                }
            }
            for u in &mut unused {
                if squared(sub(starts[i], goals[*u])) < squared(sub(starts[i], goals[goal_of[i]])) {
                    std::mem::swap(u, &mut goal_of[i]);
                    improved = true;
                }
            }
        }
        if !improved {
            return Some(goal_of);
        }
    }
}

/// Assigns `drones` to distinct goals among `goal_ids` (at least as many), near
/// each other: both are split at the median of the axis along which they spread
/// most, the goals in proportion, and each half is assigned alike.
fn bisect(
    drones: &mut [usize],
    goal_ids: &mut [usize],
    (starts, goals): (&[Point], &[Point]),
    goal_of: &mut [usize],
) {
    match drones {
        [] => return,
        [d] => {
            let nearest = goal_ids
                .iter()
                .copied()
                .min_by_key(|&g| squared(sub(starts[*d], goals[g])));
            if let Some(g) = nearest {
                goal_of[*d] = g;
            }
            return;
        }
        _ => {}
    }
    let points = drones
        .iter()
        .map(|&d| starts[d])
        .chain(goal_ids.iter().map(|&g| goals[g]));
    let axis = widest_axis(points);
    drones.sort_unstable_by_key(|&d| (starts[d][axis], d));
    goal_ids.sort_unstable_by_key(|&g| (goals[g][axis], g));
    let half = drones.len() / 2;
    // As many goals on each side as its drones need, in proportion: the first
    // half gets ⌊m·h/n⌋ ≥ h of the m ≥ n goals, the second the rest, m − ⌊m·h/n⌋ ≥ n − h.
    let goal_half = goal_ids.len() * half / drones.len();
    let (low_drones, high_drones) = drones.split_at_mut(half);
    let (low_goals, high_goals) = goal_ids.split_at_mut(goal_half);
    bisect(low_drones, low_goals, (starts, goals), goal_of);
    bisect(high_drones, high_goals, (starts, goals), goal_of);
}

/// The axis along which `points` spread the most (x first on ties).
fn widest_axis(points: impl Iterator<Item = Point>) -> usize {
    let mut low = [i32::MAX; 3];
    let mut high = [i32::MIN; 3];
    for p in points {
        for k in 0..3 {
            low[k] = low[k].min(p[k]);
            high[k] = high[k].max(p[k]);
        }
    }
    (0..3)
        .max_by_key(|&k| (i64::from(high[k]) - i64::from(low[k]), std::cmp::Reverse(k)))
        .unwrap_or(0)
}

fn sub(a: Point, b: Point) -> [i64; 3] {
    [0, 1, 2].map(|k| i64::from(a[k]) - i64::from(b[k]))
}

fn dot(a: [i64; 3], b: [i64; 3]) -> i64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn squared(a: [i64; 3]) -> i64 {
    dot(a, a)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn far() -> Instant {
        Instant::now() + Duration::from_secs(60)
    }

    /// The defining property, checked pair by pair.
    fn assert_stable(starts: &[Point], goals: &[Point], goal_of: &[usize]) {
        let mut seen = vec![false; goals.len()];
        for &g in goal_of {
            assert!(!seen[g], "goal {g} taken twice");
            seen[g] = true;
        }
        for i in 0..starts.len() {
            for j in i + 1..starts.len() {
                let ds = sub(starts[i], starts[j]);
                let dg = sub(goals[goal_of[i]], goals[goal_of[j]]);
                assert!(
                    dot(ds, dg) >= 0,
                    "drones {i} and {j} would gain by exchanging"
                );
            }
            let own = squared(sub(starts[i], goals[goal_of[i]]));
            for (g, _) in seen.iter().enumerate().filter(|(_, s)| !**s) {
                assert!(squared(sub(starts[i], goals[g])) >= own);
            }
        }
    }

    #[test]
    fn crossing_pairs_are_uncrossed() {
        let starts = [[0, 0, 0], [1, 0, 0]];
        let goals = [[0, 5, 0], [1, 5, 0]];
        let goal_of = pairwise_stable(&starts, &goals, far()).unwrap();
        assert_eq!(goal_of, vec![0, 1]);
        let reversed = [[1, 5, 0], [0, 5, 0]];
        assert_eq!(
            pairwise_stable(&starts, &reversed, far()).unwrap(),
            vec![1, 0]
        );
    }

    #[test]
    fn spare_goals_go_to_the_nearest_drones() {
        let starts = [[0, 0, 0]];
        let goals = [[9, 9, 9], [0, 0, 2], [5, 0, 0]];
        assert_eq!(pairwise_stable(&starts, &goals, far()).unwrap(), vec![1]);
    }

    #[test]
    fn too_few_goals_is_none() {
        assert_eq!(
            pairwise_stable(&[[0; 3], [1, 0, 0]], &[[0; 3]], far()),
            None
        );
    }

    #[test]
    fn a_line_into_a_square_is_stable() {
        // A line of 25 drones, shuffled goals in a 5 × 5 square above it.
        let starts: Vec<Point> = (0..25).map(|i| [i, 0, 0]).collect();
        let mut goals: Vec<Point> = (0..25).map(|i| [10 + i % 5, 3 + i / 5, 4]).collect();
        goals.reverse();
        goals.swap(3, 17);
        let goal_of = pairwise_stable(&starts, &goals, far()).unwrap();
        assert_stable(&starts, &goals, &goal_of);
    }

    #[test]
    fn a_passed_deadline_is_none() {
        let starts: Vec<Point> = (0..10).map(|i| [i, 0, 0]).collect();
        assert_eq!(pairwise_stable(&starts, &starts, Instant::now()), None);
    }
}
