// Mirrors src/integrator/control.rs: step-size control.

// STEP_UNDERFLOW (the prelude, from src/backend/gpu/shader.rs): a step
// below this fraction of max(t, 1) s is a step underflow (the f64 path's
// is 1e-15; f32 resolves a time to 6e-8 of itself).

struct StepSize { h: real, landing: bool }

// The size of the step to try from the proposed size h, at speed v and
// acceleration a in direction dir, `remaining` before the next time event.
fn step_size(h: real, steep: bool, dir: real, v: real, a: real, remaining: real) -> StepSize {
    var hh = h;
    // Approaching rest under a law steep at rest, grade the steps into the stop.
    if (steep && a * dir < 0.0) {
        let t_rest = -v / a;
        hh = min(hh, max(0.5 * t_rest, g.h_initial));
    }
    let landing = hh >= remaining;
    if (landing) { hh = remaining; }
    return StepSize(hh, landing);
}

struct Retry { h: real, underflow: bool }

// The size to try again after a rejected trial of size h, and whether it is
// too small to go on at time t.
fn retry_size(h: real, fac: real, t: real) -> Retry {
    let hh = h * min(fac, 1.0);
    return Retry(hh, hh < STEP_UNDERFLOW * max(t, 1.0));
}

fn step_factor(err: real) -> real {
    if (err > 0.0) { return clamp(0.9 * pow_r(err, -0.2), 0.2, 5.0); }
    return 5.0;
}
