// Mirrors src/integrator/flow.rs: a step's energy flow, split between the
// directions of power flow.

// Bisection ends when the bracket is P_ZERO_TOL narrow (the prelude):
// 2^-24, the resolution of f32 on [0, 1] (2^-52 in f64, `P_ZERO_TOL` in
// src/integrator/flow.rs).

// The signs of (p1, p2) throughout a mode of side c and direction s:
// p2's is -c s, p1's +1 where c s = +1, and 0 where the mode does not
// decide it (p1 with c s = -1 changes sign where rho crosses gamma).
fn mode_signs(side: i32, dir: i32) -> vec2<real> {
    let cs = real(side * dir);
    return vec2<real>(select(real(0.0), real(1.0), cs > 0.0), -cs);
}

fn dense_slope(r: array<real, 5>, th: real) -> real {
    let th1 = 1.0 - th;
    return r[1] + (th1 - th) * r[2] + th * (2.0 - 3.0 * th) * r[3] + 2.0 * th * th1 * (th1 - th) * r[4];
}

// [in, out] parts of a step's increment r[1] of the integral of p, from
// its dense output r (r0 = 0) and p at the step's start and end, and how
// far they may be off (z: `split_error`, 0 where p keeps its sign).
fn split(r: array<real, 5>, p0: real, p_end: real) -> vec3<real> {
    if (crosses(p0, p_end)) { return split_crossing(r, p0); }
    if (!agrees(r[1], p0, p_end)) { return split_against(r); }
    return vec3<real>(split_whole(r[1], p0, p_end), 0.0);
}

// Whether a step's increment of the integral of p has the sign of p at
// the step's ends (either may be zero): else p took the other sign inside
// the step, and the ends do not say which part the increment goes to.
fn agrees(total: real, p0: real, p_end: real) -> bool {
    return total * (p0 + p_end) >= 0.0;
}

// Whether an increment goes whole to the part of p's sign at the ends: p
// keeps its sign there, and the increment has it too or is within its own
// error estimate est (`goes_whole`).
fn goes_whole(total: real, est: real, p0: real, p_end: real) -> bool {
    let noise = abs(total) <= est && p0 + p_end != 0.0;
    return !crosses(p0, p_end) && (agrees(total, p0, p_end) || noise);
}

// `split` where the increment has the other sign than p at the ends: it
// goes to the part of its own sign (`split_whole` with the increment in
// place of p), and either part may be off by the area of p's other sign,
// within |r1| + |r2| + |r3| + |r4|.
fn split_against(r: array<real, 5>) -> vec3<real> {
    let parts = split_whole(r[1], r[1], 0.0);
    return vec3<real>(parts, abs(r[1]) + abs(r[2]) + abs(r[3]) + abs(r[4]));
}

// Whether p changes sign inside a step (a zero at an end is no crossing).
fn crosses(p0: real, p_end: real) -> bool {
    return p0 * p_end < 0.0;
}

// `split` of an increment where p keeps its sign: all of it to one part.
fn split_whole(total: real, p0: real, p_end: real) -> vec2<real> {
    let positive = p0 + p_end > 0.0 || (p0 + p_end == 0.0 && total >= 0.0);
    return select(vec2<real>(0.0, -total), vec2<real>(total, 0.0), positive);
}

// `split` where p changes sign inside the step: the zero by bisection.
fn split_crossing(r: array<real, 5>, p0: real) -> vec3<real> {
    let total = r[1];
    let sign = select(real(-1.0), real(1.0), p0 > 0.0);
    var a: real = 0.0;
    var b: real = 1.0;
    // A trip count the compiler cannot see: a constant one is unrolled,
    // and that code, run only at a crossing, halved lavapipe's throughput.
    var it = 0u;
    while (b - a > P_ZERO_TOL && it < 64u) {
        it++;
        let c = 0.5 * (a + b);
        if (sign * dense_slope(r, c) > 0.0) { a = c; } else { b = c; }
    }
    let th = 0.5 * (a + b);
    let first = dense_v(r, th);
    let rest = total - first;
    let parts = select(vec2<real>(rest, -first), vec2<real>(first, -rest), sign > 0.0);
    return vec3<real>(parts, split_error(r, th));
}

// How far `split`'s parts may be off where p changes sign at th inside
// the step: th^2 (1 - th)^2 |r4| (see src/integrator/flow.rs).
fn split_error(r: array<real, 5>, th: real) -> real {
    let w = th * (1.0 - th);
    return w * w * abs(r[4]);
}

fn dense_w(dw: real, h: real, q0: real, q_end: real, r4: real) -> array<real, 5> {
    let r2 = h * q0 - dw;
    return array<real, 5>(0.0, dw, r2, dw - h * q_end - r2, r4);
}

// Whether p turned and turned back inside a step: the same sign at both
// ends, the other at the middle of its dense output. The split cannot see
// it; the row is recomputed in f64 (`Recheck::FlowTurn`). (The f64 path's
// steps, a hundred times tighter, were not seen to miss one.)
fn turns_inside(r: array<real, 5>, p0: real, p_end: real) -> bool {
    return !crosses(p0, p_end) && dense_slope(r, 0.5) * (p0 + p_end) < 0.0;
}

// Whether p1, where the mode does not decide its part, turned and turned
// back inside an accepted step of mode m.
fn flow_turns(k1: array<real, NY>, tr: Trial, h: real, m: Mode) -> bool {
    if (mode_signs(m.side, m.dir).x != 0.0) { return false; }
    // p1 at the step's start and end.
    let a = powers(k1[4], k1[5]);
    let b = powers(tr.k7[4], tr.k7[5]);
    return turns_inside(dense_w(tr.dw.x, h, a.x, b.x, tr.dw_r4.x), a.x, b.x);
}

// A step's energy flow: the increments of (w1_in, w1_out, w2_in,
// w2_out), and how far the split of the integrals of p1 and p2 may be off.
struct Flow { d: vec4<real>, err: vec2<real> }

// The flow of an accepted step of mode m: each increment whole to the
// part the mode gives it, p1's where it gives none by its ends' signs.
fn step_flow(k1: array<real, NY>, tr: Trial, h: real, m: Mode) -> Flow {
    let sg = mode_signs(m.side, m.dir);
    var f1 = vec3<real>(split_whole(tr.dw.x, sg.x, 0.0), 0.0);
    if (sg.x == 0.0) {
        let a = powers(k1[4], k1[5]);
        let b = powers(tr.k7[4], tr.k7[5]);
        if (goes_whole(tr.dw.x, tr.est[5], a.x, b.x)) {
            f1 = vec3<real>(split_whole(tr.dw.x, a.x, b.x), 0.0);
        } else {
            f1 = split(dense_w(tr.dw.x, h, a.x, b.x, tr.dw_r4.x), a.x, b.x);
        }
    }
    let f2 = split_whole(tr.dw.y, sg.y, 0.0);
    return Flow(vec4<real>(f1.xy, f2), vec2<real>(f1.z, 0.0));
}
