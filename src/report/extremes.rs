//! The range of each plotted result over a run's finished lanes, for
//! what the report says first.

/// The smallest and largest value of a result, and the first lanes that
/// have them (none while no lane has a value).
#[derive(Clone, Copy, Debug)]
pub struct Extreme {
    pub min: (f64, u64),
    pub max: (f64, u64),
    pub count: u64,
    /// Values <= 0 (an inverse efficiency's self-locking lanes).
    pub at_most_zero: u64,
    /// Finished lanes at rest, left out of a running value's range (no
    /// running point).
    pub at_rest: u64,
}

impl Default for Extreme {
    fn default() -> Self {
        Extreme {
            min: (f64::INFINITY, 0),
            max: (f64::NEG_INFINITY, 0),
            count: 0,
            at_most_zero: 0,
            at_rest: 0,
        }
    }
}

impl Extreme {
    pub(super) fn add(&mut self, lane: u64, v: f64) {
        if !v.is_finite() {
            return;
        }
        self.count += 1;
        if v <= 0.0 {
            self.at_most_zero += 1;
        }
        if v < self.min.0 {
            self.min = (v, lane);
        }
        if v > self.max.0 {
            self.max = (v, lane);
        }
    }
}
