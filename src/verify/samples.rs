//! The shape the samples must have before anything is measured: every drone
//! sampled at the same times, stepping by one constant period.

/// Why the samples could not be checked at all.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CheckError {
    /// Drones sampled a different number of times.
    #[error(
        "drone {drone} has {found} samples, drone 0 has {expected}: all must share sample times"
    )]
    SampleCount {
        /// The drone, by index in the samples.
        drone: usize,
        /// Drone 0's sample count.
        expected: usize,
        /// This drone's.
        found: usize,
    },
    /// Drones sampled at different times.
    #[error("drone {drone}, sample {index}: time {found} s differs from drone 0's {expected} s")]
    SampleTime {
        /// The drone, by index in the samples.
        drone: usize,
        /// The sample, by index.
        index: usize,
        /// Drone 0's time there, seconds.
        expected: f64,
        /// This drone's, seconds.
        found: f64,
    },
    /// The sample times do not step by one constant period (the margin between
    /// samples depends on it).
    #[error("sample times must increase at a constant period (sample {index})")]
    Period {
        /// The first sample off the period.
        index: usize,
    },
}

/// The samples' common times, once every drone is sampled at the same times at a
/// constant period.
pub(super) fn validate_times(samples: &[Vec<[f64; 4]>]) -> Result<Vec<f64>, CheckError> {
    let Some(first) = samples.first() else {
        return Ok(Vec::new());
    };
    let times: Vec<f64> = first.iter().map(|s| s[0]).collect();
    if times.len() > 1 {
        let period = times[1] - times[0];
        for (index, w) in times.windows(2).enumerate() {
            if period.is_nan()
                || period <= 0.0
                || ((w[1] - w[0]) - period).abs() > 1e-6 * period.max(1.0)
            {
                return Err(CheckError::Period { index: index + 1 });
            }
        }
    }
    for (drone, s) in samples.iter().enumerate() {
        if s.len() != times.len() {
            return Err(CheckError::SampleCount {
                drone,
                expected: times.len(),
                found: s.len(),
            });
        }
        for (index, (sample, &t)) in s.iter().zip(&times).enumerate() {
            if (sample[0] - t).abs() > 1e-9 {
                return Err(CheckError::SampleTime {
                    drone,
                    index,
                    expected: t,
                    found: sample[0],
                });
            }
        }
    }
    Ok(times)
}
