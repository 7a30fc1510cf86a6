//! The integrated state's components, in order: x1, ẋ1, w_motor, w_load,
//! w_friction and w_p1 = ∫p1 dt (docs/model.md sections 6 and 10; ∫p2 dt
//! is w_friction − w_p1). The in and out parts of section 10 are not
//! components: see `flow`.

/// How many components the state has.
pub const NY: usize = 6;

/// The mesh powers (p1, p2) from a derivative's components 4 and 5
/// (w_friction's rate p1 + p2, and ∫p1's rate p1): the one place that
/// says which components they are.
#[inline(always)]
pub(crate) fn powers(k4: f64, k5: f64) -> (f64, f64) {
    (k5, k4 - k5)
}
