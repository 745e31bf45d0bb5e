//! A straight line on the voxel grid: a drone moves one voxel along one axis per
//! step, so it flies a staircase close to its line, paced so that every drone of
//! a leg arrives at the same step, as on CAPT's synchronised lines.

use super::assignment::Point;

/// Ways to fly one line: how the line's progress is rounded to whole moves
/// (to the nearest, down, up) times which axis goes first when two lag alike.
pub(super) const VARIANTS: u8 = 18;

/// Axis orders for ties, one per permutation of x, y, z.
const TIE_ORDERS: [[usize; 3]; 6] = [
    [0, 1, 2],
    [1, 2, 0],
    [2, 0, 1],
    [0, 2, 1],
    [1, 0, 2],
    [2, 1, 0],
];

/// The voxels from `from` to `to` at every step `0..=steps` (so `steps + 1` of
/// them): a move at each step where the line's progress, rounded, asks for one,
/// along the axis that lags its share of the line the most. Every axis is thus
/// less than two voxels off the line at every step, and mostly less than one. `steps` must be at least the
/// moves needed (the Manhattan distance); with more, the moves are spread out.
/// `variant` (below [`VARIANTS`]; 0 rounds to the nearest, x first) picks
/// another rounding and order of axes: a nearby staircase of the same line.
pub(super) fn staircase(from: Point, to: Point, steps: u32, variant: u8) -> Vec<Point> {
    let rounding = usize::from(variant % 3);
    let order = TIE_ORDERS[usize::from(variant / 3) % TIE_ORDERS.len()];
    let moves = [0, 1, 2].map(|k| i64::from(to[k]) - i64::from(from[k]));
    let length: i64 = moves.iter().map(|m| m.abs()).sum();
    let steps_i = i64::from(steps);
    debug_assert!(
        length <= steps_i,
        "a staircase needs {length} steps, got {steps}"
    );
    let mut done = [0i64; 3];
    let mut at = from;
    let mut path = Vec::with_capacity(steps as usize + 1);
    path.push(at);
    for t in 1..=steps_i {
        // length · t / steps moves are due by step t, rounded to the nearest,
        // down or up: at most one more each step, all of them by the last.
        let offset = [steps_i, 0, 2 * steps_i - 2][rounding];
        let due = (2 * length * t + offset) / (2 * steps_i);
        if done.iter().sum::<i64>() < due {
            let lag = |k: usize| moves[k].abs() * t - done[k] * steps_i;
            let rank = |k: usize| order.iter().position(|&o| o == k).unwrap_or(3);
            let axis = (0..3)
                .filter(|&k| done[k] < moves[k].abs())
                .max_by_key(|&k| (lag(k), std::cmp::Reverse(rank(k))));
            if let Some(k) = axis {
                done[k] += 1;
                at[k] += moves[k].signum() as i32;
            }
        }
        path.push(at);
    }
    path
}

#[cfg(test)]
mod tests {
    use super::*;

    fn manhattan(a: Point, b: Point) -> i32 {
        (0..3).map(|k| (a[k] - b[k]).abs()).sum()
    }

    #[test]
    fn a_diagonal_alternates_its_axes() {
        let path = staircase([0, 0, 0], [2, 2, 0], 4, 0);
        assert_eq!(
            path,
            vec![[0, 0, 0], [1, 0, 0], [1, 1, 0], [2, 1, 0], [2, 2, 0]]
        );
    }

    #[test]
    fn spare_steps_are_spread_as_waits() {
        let path = staircase([0, 0, 0], [0, 0, -2], 4, 0);
        assert_eq!(
            path,
            vec![[0, 0, 0], [0, 0, -1], [0, 0, -1], [0, 0, -2], [0, 0, -2]]
        );
        assert_eq!(staircase([3, 3, 3], [3, 3, 3], 0, 0), vec![[3, 3, 3]]);
    }

    #[test]
    fn every_step_is_one_move_or_a_wait_and_stays_near_the_line() {
        for (to, steps) in [
            ([7, -3, 5], 15),
            ([1, 9, -4], 20),
            ([-6, 0, 2], 8),
            ([5, 5, 5], 40),
        ] {
            for variant in 0..VARIANTS {
                let path = staircase([0, 0, 0], to, steps, variant);
                assert_eq!(path.len(), steps as usize + 1);
                assert_eq!(path[steps as usize], to);
                for (t, pair) in path.windows(2).enumerate() {
                    assert!(manhattan(pair[0], pair[1]) <= 1, "jump at step {t}");
                }
                for (t, p) in path.iter().enumerate() {
                    let share = t as f64 / f64::from(steps);
                    for k in 0..3 {
                        let line = f64::from(to[k]) * share;
                        assert!(
                            (f64::from(p[k]) - line).abs() < 2.0,
                            "{to:?} in {steps}: axis {k} at step {t} is {} off its line",
                            f64::from(p[k]) - line
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn variants_round_and_order_otherwise() {
        // One move in two steps: at the nearest (step 1), late (2) or early (1).
        let at_step_1 = |v| staircase([0, 0, 0], [1, 0, 0], 2, v)[1];
        assert_eq!([0, 1, 2].map(at_step_1), [[1, 0, 0], [0, 0, 0], [1, 0, 0]]);
        // A tie between x and y: x first, then y first.
        assert_eq!(staircase([0, 0, 0], [1, 1, 0], 2, 0)[1], [1, 0, 0]);
        assert_eq!(staircase([0, 0, 0], [1, 1, 0], 2, 3)[1], [0, 1, 0]);
    }
}
