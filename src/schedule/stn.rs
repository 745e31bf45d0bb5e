//! A Simple Temporal Network: timepoints and `[lower, upper]` bounds on their differences.
//!
//! Timepoint 0 is the origin (time zero). A constraint `from → to` with bounds
//! `[lower_s, upper_s]` means `lower_s ≤ t(to) − t(from) ≤ upper_s`; `upper_s` may be
//! infinite. When every upper bound is infinite the network is a DAG of lower bounds
//! (the case the scheduler produces), solved exactly by a longest path in O(V + E).
//! Finite upper bounds (time windows, synchronised arrivals) need the general
//! Bellman–Ford check on the distance graph, [`Stn::solve_general`].

use super::ScheduleError;
use petgraph::algo::{bellman_ford, kosaraju_scc, toposort};
use petgraph::graph::{DiGraph, NodeIndex};
use serde::{Deserialize, Serialize};

/// `lower_s ≤ t(to) − t(from) ≤ upper_s`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Constraint {
    /// The earlier timepoint.
    pub from: u32,
    /// The later timepoint.
    pub to: u32,
    /// Least time from `from` to `to`, seconds (may be negative).
    pub lower_s: f64,
    /// `f64::INFINITY` for "no upper bound" (serialised as `null`).
    #[serde(with = "infinite_as_null")]
    pub upper_s: f64,
}

/// A simple temporal network. Timepoint 0 is the origin.
///
/// ```
/// use swarmctl::schedule::Stn;
/// let mut stn = Stn::new(3);
/// stn.add(0, 1, 2.0, f64::INFINITY);
/// stn.add(1, 2, 1.5, f64::INFINITY);
/// stn.add(0, 2, 4.0, f64::INFINITY);
/// let t = stn.earliest_dag().unwrap();
/// assert_eq!(t, vec![0.0, 2.0, 4.0]);
/// assert_eq!(stn.solve_general().unwrap(), t);
/// ```
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Stn {
    /// Number of timepoints, the origin included; they are `0..timepoints`.
    pub timepoints: u32,
    /// Every bound, in the order added.
    pub constraints: Vec<Constraint>,
}

/// Why a DAG longest path was not possible: the timepoints on a cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct StnCycle {
    /// Every strongly connected component with more than one timepoint (or a self-loop).
    pub components: Vec<Vec<u32>>,
}

impl Stn {
    /// A network of `timepoints` timepoints (including the origin) and no constraints.
    pub fn new(timepoints: u32) -> Self {
        Self {
            timepoints: timepoints.max(1),
            constraints: Vec::new(),
        }
    }

    /// Adds `lower_s ≤ t(to) − t(from) ≤ upper_s`.
    pub fn add(&mut self, from: u32, to: u32, lower_s: f64, upper_s: f64) {
        self.constraints.push(Constraint {
            from,
            to,
            lower_s,
            upper_s,
        });
    }

    fn lower_graph(&self) -> DiGraph<(), f64, u32> {
        let mut g = DiGraph::with_capacity(self.timepoints as usize, self.constraints.len());
        for _ in 0..self.timepoints {
            g.add_node(());
        }
        for c in &self.constraints {
            g.add_edge(
                NodeIndex::new(c.from as usize),
                NodeIndex::new(c.to as usize),
                c.lower_s,
            );
        }
        g
    }

    /// A topological order of the lower-bound graph, or its cycles.
    pub fn topological_order(&self) -> Result<Vec<u32>, StnCycle> {
        let g = self.lower_graph();
        match toposort(&g, None) {
            Ok(order) => Ok(order.into_iter().map(|n| n.index() as u32).collect()),
            Err(_) => {
                let components = kosaraju_scc(&g)
                    .into_iter()
                    .filter(|c| c.len() > 1 || g.contains_edge(c[0], c[0]))
                    .map(|c| c.into_iter().map(|n| n.index() as u32).collect())
                    .collect();
                Err(StnCycle { components })
            }
        }
    }

    /// Earliest times when all upper bounds are infinite: the longest path from the
    /// origin in the DAG of lower bounds, O(V + E). Timepoints the origin does not reach
    /// get time zero (they are unconstrained from below). This is the minimum of every
    /// timepoint over all solutions, so the makespan it gives is the network's minimum.
    pub fn earliest_dag(&self) -> Result<Vec<f64>, ScheduleError> {
        let order = self
            .topological_order()
            .map_err(|_| ScheduleError::Inconsistent)?;
        if self.constraints.iter().any(|c| c.upper_s.is_finite()) {
            return self.solve_general();
        }
        Ok(self.earliest_in_order(&order))
    }

    /// Latest times such that every timepoint with `deadline_s[i]` finite stays at or
    /// below it, for a DAG of lower bounds: reverse topological order, O(V + E).
    pub fn latest_dag(&self, order: &[u32], deadline_s: &[f64]) -> Vec<f64> {
        let (start, adj) = self.successors();
        let mut latest = deadline_s.to_vec();
        for &u in order.iter().rev() {
            let u = u as usize;
            let mut l = latest[u];
            for &(v, lower_s) in &adj[start[u] as usize..start[u + 1] as usize] {
                l = l.min(latest[v as usize] - lower_s);
            }
            latest[u] = l;
        }
        latest
    }

    /// Longest paths from the origin over a topological order of a DAG of lower bounds
    /// (upper bounds are ignored): O(V + E).
    pub fn earliest_in_order(&self, order: &[u32]) -> Vec<f64> {
        let (start, adj) = self.successors();
        let mut t = vec![0.0f64; self.timepoints as usize];
        for &u in order {
            let u = u as usize;
            let tu = t[u];
            for &(v, lower_s) in &adj[start[u] as usize..start[u + 1] as usize] {
                if tu + lower_s > t[v as usize] {
                    t[v as usize] = tu + lower_s;
                }
            }
        }
        t
    }

    /// Successor lists in compressed form: `adj[start[u]..start[u + 1]]` are `u`'s
    /// `(to, lower_s)` pairs.
    fn successors(&self) -> (Vec<u32>, Vec<(u32, f64)>) {
        let n = self.timepoints as usize;
        let mut start = vec![0u32; n + 1];
        for c in &self.constraints {
            start[c.from as usize + 1] += 1;
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut adj = vec![(0u32, 0.0f64); self.constraints.len()];
        for c in &self.constraints {
            adj[fill[c.from as usize] as usize] = (c.to, c.lower_s);
            fill[c.from as usize] += 1;
        }
        (start, adj)
    }

    /// Earliest times for general bounds: Bellman–Ford on the distance graph, O(V·E).
    /// `t(to) − t(from) ≥ lower` becomes the edge `to → from` of weight `−lower`, and
    /// `t(to) − t(from) ≤ upper` the edge `from → to` of weight `upper`; the earliest
    /// time of `i` is minus the shortest distance from `i` to the origin, computed as a
    /// shortest path from the origin in the reversed distance graph. A negative cycle
    /// means the network is inconsistent.
    pub fn solve_general(&self) -> Result<Vec<f64>, ScheduleError> {
        let mut g: DiGraph<(), f64, u32> = DiGraph::new();
        for _ in 0..self.timepoints {
            g.add_node(());
        }
        for c in &self.constraints {
            let (from, to) = (
                NodeIndex::new(c.from as usize),
                NodeIndex::new(c.to as usize),
            );
            // Reversed distance graph: reverse each distance-graph edge.
            g.add_edge(from, to, -c.lower_s);
            if c.upper_s.is_finite() {
                g.add_edge(to, from, c.upper_s);
            }
        }
        // Every timepoint is at or after the origin.
        for i in 1..self.timepoints {
            g.add_edge(NodeIndex::new(0), NodeIndex::new(i as usize), 0.0);
        }
        let paths = bellman_ford(&g, NodeIndex::new(0)).map_err(|_| ScheduleError::Inconsistent)?;
        if paths.distances[0] < 0.0 {
            return Err(ScheduleError::Inconsistent);
        }
        Ok(paths
            .distances
            .iter()
            .map(|d| if *d == 0.0 { 0.0 } else { -d })
            .collect())
    }
}

mod infinite_as_null {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(value: &f64, s: S) -> Result<S::Ok, S::Error> {
        if value.is_finite() {
            s.serialize_some(value)
        } else {
            s.serialize_none()
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::INFINITY))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cycle_is_reported_with_its_timepoints() {
        let mut stn = Stn::new(4);
        stn.add(0, 1, 1.0, f64::INFINITY);
        stn.add(1, 2, 1.0, f64::INFINITY);
        stn.add(2, 1, 1.0, f64::INFINITY);
        let cycle = stn.topological_order().unwrap_err();
        let mut c = cycle.components[0].clone();
        c.sort();
        assert_eq!(c, vec![1, 2]);
        assert_eq!(stn.earliest_dag(), Err(ScheduleError::Inconsistent));
    }

    #[test]
    fn upper_bounds_are_honoured_or_rejected() {
        let mut stn = Stn::new(3);
        stn.add(0, 1, 1.0, 2.0);
        stn.add(0, 2, 5.0, f64::INFINITY);
        stn.add(1, 2, 0.0, 3.5); // forces t1 >= 1.5
        assert_eq!(stn.solve_general().unwrap(), vec![0.0, 1.5, 5.0]);
        stn.add(1, 2, 0.0, 2.0); // t1 >= 3 contradicts t1 <= 2
        assert_eq!(stn.solve_general(), Err(ScheduleError::Inconsistent));
    }

    #[test]
    fn latest_times_give_slack_off_the_critical_path() {
        let mut stn = Stn::new(4);
        stn.add(0, 1, 1.0, f64::INFINITY);
        stn.add(0, 2, 3.0, f64::INFINITY);
        stn.add(1, 3, 1.0, f64::INFINITY);
        stn.add(2, 3, 1.0, f64::INFINITY);
        let order = stn.topological_order().unwrap();
        let early = stn.earliest_dag().unwrap();
        assert_eq!(early[3], 4.0);
        let mut deadline = vec![f64::INFINITY; 4];
        deadline[3] = early[3];
        let late = stn.latest_dag(&order, &deadline);
        assert_eq!(late, vec![0.0, 3.0, 3.0, 4.0]);
    }
}
