//! The report's small words and numbers: a parameter's axis label, a
//! share as a percentage with its interval, "1 lane" and "435 lanes".
//! Every section uses them, so they live here rather than in `mod.rs`
//! (a child importing from its folder's `mod.rs` would be an import
//! circle).

use crate::params::Param;
use crate::stats::wilson;

/// A grid axis with at most this many values is drawn as points at its
/// values (a category each), not as a line that would suggest values in
/// between.
pub(super) const FEW: usize = 8;

/// "meaning, name (unit)": a parameter's axis label.
pub(crate) fn param_label(p: Param) -> String {
    match p {
        Param::Num(n) => crate::columns::label(n.name(), n.def().meaning, n.def().unit),
        Param::Motor => crate::columns::label(p.name(), "motor law", ""),
        Param::Friction => crate::columns::label(p.name(), "friction law", ""),
        Param::FrictionTable => crate::columns::label(p.name(), "friction table (material)", ""),
    }
}

/// A share as a percentage: two decimals, or two significant digits
/// below 0.01 % (the upper end of a Wilson interval for no lane of a
/// million is 3.8e-4 %, not 0.00 %); "-" for none.
pub(crate) fn percent(x: f64) -> String {
    if !x.is_finite() {
        "-".into()
    } else if x > 0.0 && x < 1e-4 {
        format!("{:.1e} %", 100.0 * x)
    } else if x < 1.0 && x > 1.0 - 1e-4 {
        // Likewise just below 100 %: enough decimals to tell it from 100.
        let decimals = (-(1.0 - x).log10()).ceil() as usize - 1;
        format!("{:.*} %", decimals, 100.0 * x)
    } else {
        format!("{:.2} %", 100.0 * x)
    }
}

/// "1 lane", "435 lanes".
pub(crate) fn lanes_text(n: u64) -> String {
    format!("{n} lane{}.", plural(n))
}

/// "s" unless `n` is 1.
pub(crate) fn plural(n: u64) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

/// The 95 % Wilson interval of k/n where the lanes are independent
/// draws; none (NaN) otherwise.
pub(crate) fn interval(k: u64, n: u64, independent: bool) -> (f64, f64) {
    if independent {
        wilson(k, n)
    } else {
        (f64::NAN, f64::NAN)
    }
}

/// A share with its 95 % Wilson interval, as table cells ("-" where the
/// lanes are not independent draws).
pub(crate) fn share_cells(k: u64, n: u64, independent: bool) -> [String; 3] {
    let (lo, hi) = interval(k, n, independent);
    if lo.is_nan() {
        return [k.to_string(), percent(k as f64 / n as f64), "-".into()];
    }
    [
        k.to_string(),
        percent(k as f64 / n as f64),
        format!("{} to {}", percent(lo), percent(hi)),
    ]
}
