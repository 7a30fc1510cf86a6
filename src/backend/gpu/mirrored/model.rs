//! The model's functions that the shader mirrors, compared by what they
//! compute: a small compute entry point beside the shader's own runs
//! each WGSL function (the kernel's formulas, the motor, μ of every
//! friction law and its branch, φ, ψ's parts, the equation of motion, the
//! stick test) on a grid of lanes, speeds and modes (every law and motor,
//! both contact sides and directions, the motor on and cut, both
//! branches, rest, the laws' branch speeds, the motor's synchronous speed)
//! on an adapter, and each value is held to the Rust function's (f64) to
//! f32's bound: 2e-5 of the scale of what it is made from (a force's or
//! an acceleration's terms, not its own value, which may cancel to 0),
//! and equal where it is a decision (a side, a branch, a stick). Without
//! an adapter the test says why it is skipped, unless TSWM_REQUIRE_GPU=1.

use super::{values, Run, Tally, BOUND};
use crate::input::sampling::Uniforms;
use crate::integrator::events::{event_value, locate_root, EventFn};
use crate::integrator::rhs::rhs;
use crate::model::{self, kernel, FrictionKind, FrictionTable, Lane, Mode, MotorKind};
use crate::params::table_name::TableName;
use crate::params::{Num, Param, Spec};

/// Values a case: see `ENTRY`.
const K: usize = 36;

/// Lane `c.x` at speed `bitcast<f32>(c.y)` in the mode of flags `c.z`
/// (1: side +1, 2: dir +1, 4: motor on; the bits from 8 up: the branch).
pub(super) const ENTRY: &str = r#"
@compute @workgroup_size(64)
fn mirrored(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= arrayLength(&d_cases)) {
        return;
    }
    let c = d_cases[i];
    let l = d_lanes[c.x];
    let v = bitcast<f32>(c.y);
    let m = Mode(select(-1, 1, (c.z & 1u) != 0u), select(-1, 1, (c.z & 2u) != 0u),
                 (c.z & 4u) != 0u, c.z >> 3u);
    let o = i * 36u;
    let vs = sliding_speed(f32(m.dir), v, l.inv_cos_g);
    let f1 = motor_force(l, v, m.motor_on);
    let load = load_term(l.f2, l.m2, l.tan_g);
    let mu = mu_sliding(l, vs, m.branch);
    let t = f32(m.side * m.dir) * mu;
    let pq = psi_parts(l.tan_g, t);
    let mo = motion(l, m, v);
    let st = stick_test(l, m.motor_on);
    d_out[o] = kloss(l.v_sync, l.sigma_k, l.f_crit, v);
    d_out[o + 1u] = motor_force_of(l.motor, m.motor_on, l.f1, l.v_sync, l.sigma_k, l.f_crit, v);
    d_out[o + 2u] = paper_rho(l.law[0], l.law[1], l.law[2], vs);
    d_out[o + 3u] = vs;
    d_out[o + 4u] = load;
    d_out[o + 5u] = switching(f1, l.m1, load);
    d_out[o + 6u] = pq.x;
    d_out[o + 7u] = pq.y;
    d_out[o + 8u] = mo.acc;
    d_out[o + 9u] = mo.d;
    d_out[o + 10u] = mo.f1;
    d_out[o + 11u] = mo.s1;
    d_out[o + 12u] = mo.s2;
    d_out[o + 13u] = mu;
    d_out[o + 14u] = phi(l, v, m.motor_on);
    d_out[o + 15u] = f32(side_of(phi(l, v, m.motor_on)));
    d_out[o + 16u] = f1;
    d_out[o + 17u] = f32(branch_of(l, vs));
    d_out[o + 18u] = tan_small(0.01 * v);
    d_out[o + 19u] = agma_mu(vs, m.branch == 1u);
    d_out[o + 20u] = st.x;
    d_out[o + 21u] = st.y;
    let dv = rhs(l, m, v);
    for (var j = 0u; j < NY; j++) {
        d_out[o + 22u + j] = dv.k[j];
    }
    d_out[o + 28u] = dv.d;
    for (var e = 0u; e < 4u; e++) {
        d_out[o + 29u + e] = event_value(l, m, e, v);
    }
    // A step from v to -v/2 (its dense output): where it comes to rest.
    let r = array<real, 5>(v, -1.5 * v, 0.1 * v, 0.05 * v, 0.0);
    d_out[o + 33u] = locate_root(l, m, EV_REST, r, event_value(l, m, EV_REST, -0.5 * v));
}
"#;

/// The names of the values, for the messages.
const NAMES: [&str; 34] = [
    "kloss",
    "motor_force_of",
    "paper_rho",
    "sliding_speed",
    "load_term",
    "switching",
    "psi_parts.p",
    "psi_parts.q",
    "motion.acc",
    "motion.d",
    "motion.f1",
    "motion.s1",
    "motion.s2",
    "mu_sliding",
    "phi",
    "side_of",
    "motor_force",
    "branch_of",
    "tan_small",
    "agma_mu",
    "stick_test.sticks",
    "stick_test.t",
    "rhs.x1",
    "rhs.v1",
    "rhs.w_motor",
    "rhs.w_load",
    "rhs.w_friction",
    "rhs.w_p1",
    "rhs.d",
    "event_value(switch)",
    "event_value(rest)",
    "event_value(speeding)",
    "event_value(branch)",
    "locate_root(rest)",
];

/// Lanes of every friction law and motor, with random designs.
pub(super) fn lanes(tables: &[FrictionTable]) -> Vec<Lane> {
    let names = [TableName::new("bronze").unwrap()];
    let mut u = Uniforms::new(77);
    let mut out = Vec::new();
    for law in FrictionKind::ALL {
        for k in 0..12 {
            let mut s = Spec::default();
            s.set(Num::GammaDeg, 2.0 + 30.0 * u.next());
            s.set(Num::F2, -9000.0 + 18000.0 * u.next());
            s.set(Num::M1, 586.0 * (0.5 + u.next()));
            s.set(Num::M2, 10275.0 * (0.5 + u.next()));
            s.friction = Some(law);
            match law {
                FrictionKind::Paper => s.set(Num::FricB, 0.1 + 2.0 * u.next()),
                FrictionKind::Coulomb => s.set(Num::Mu, 0.02 + 0.1 * u.next()),
                FrictionKind::Stribeck => {
                    let mu = 0.02 + 0.08 * u.next();
                    s.set(Num::Mu, mu);
                    s.set(Num::MuStatic, mu * (1.0 + u.next()));
                    s.set(Num::VStribeck, 0.01 + 0.5 * u.next());
                    s.set(Num::StribeckExp, 0.5 + 1.5 * u.next());
                    s.set(Num::MuViscous, 0.01 * u.next());
                }
                FrictionKind::Table => {
                    s.set_text(Param::FrictionTable, "bronze").unwrap();
                }
                _ => {}
            }
            if k % 3 == 0 {
                s.motor = Some(MotorKind::Constant);
                s.set(Num::F1, 6000.0 * u.next());
            }
            let p = s.resolve(&names).unwrap_or_else(|e| panic!("{law:?}: {e}"));
            out.push(Lane::new(&p, tables));
        }
    }
    out
}

/// The Rust (f64) values of a case, and the scale each is held to.
fn cpu(l: &Lane, tables: &[FrictionTable], m: Mode, v: f64) -> Vec<(f64, f64)> {
    let vs = kernel::sliding_speed(m.dir as f64, v, l.inv_cos_g);
    let f1 = model::motor_force(l, v, m.motor_on);
    let load = kernel::load_term(l.f2, l.m2, l.tan_g);
    let mu = model::friction::mu_sliding(l, tables, vs, m.branch);
    let t = (m.side * m.dir) as f64 * mu;
    let (p, q) = kernel::psi_parts(l.tan_g, t);
    let mo = model::motion(l, tables, m, v);
    let ph = model::phi(l, v, m.motor_on);
    let (sticks, st) = model::stick_test(l, m.motor_on);
    let force = l.f_crit.max(l.f1.abs()) + l.f2.abs();
    let acc = force / l.m1 + kernel::load_term(l.f2, l.m2, l.tan_g).abs();
    let [a, b, c, ..] = l.law;
    let big = force * (1.0 + p.abs()) / q.abs().max(1e-3);
    let agma = model::agma_mu(vs, m.branch == 1);
    let mut out = vec![
        (kernel::kloss(l.v_sync, l.sigma_k, l.f_crit, v), l.f_crit),
        (
            kernel::motor_force_of(l.motor, m.motor_on, l.f1, l.v_sync, l.sigma_k, l.f_crit, v),
            force,
        ),
        (
            kernel::paper_rho(a, b, c, vs),
            kernel::paper_rho(a, b, c, vs).abs(),
        ),
        (vs, vs.abs().max(1e-30)),
        (load, load.abs()),
        (kernel::switching(f1, l.m1, load), acc),
        (p, 1.0 + l.tan_g + t.abs()),
        (q, 1.0 + l.tan_g * t.abs()),
        (mo.acc, acc * (1.0 + p.abs()) / q.abs().max(1e-3)),
        (mo.d, mo.d.abs() + l.m1),
        (mo.f1, force),
        (mo.s1, force * (1.0 + p.abs()) / q.abs().max(1e-3)),
        (mo.s2, force * (1.0 + p.abs()) / q.abs().max(1e-3)),
        (mu, mu_scale(l, tables, m.branch, mu)),
        (ph, acc),
        (model::side_of(ph) as f64, 0.0),
        (f1, force),
        (f64::from(model::branch_of(l, tables, vs)), 0.0),
        (model::friction::tan_small(0.01 * v), (0.01 * v).abs()),
        (agma, agma),
        (if sticks { 1.0 } else { 0.0 }, 0.0),
        (st, force),
    ];
    let (k, d) = rhs(l, tables, m, v);
    let power = big * v.abs() * (1.0 + l.tan_g);
    out.extend([
        (k[0], v.abs()),
        (k[1], acc * (1.0 + p.abs()) / q.abs().max(1e-3)),
        (k[2], force * v.abs()),
        (k[3], l.f2.abs() * v.abs() * l.tan_g),
        (k[4], power),
        (k[5], power),
        (d, mo.d.abs() + l.m1),
    ]);
    let which = [
        EventFn::Switch,
        EventFn::Rest,
        EventFn::Speeding,
        EventFn::Branch,
    ];
    let (lo, hi) = model::branch_edges(l, tables, m.branch);
    let edges = lo.abs().min(1e30) + hi.abs().min(1e30);
    let speeding = big / l.m1 * (mo.d.abs() + l.m1); // −s·ẍ1·D
    let scales = [acc, v.abs(), speeding, vs.abs() + edges];
    for (w, sc) in which.into_iter().zip(scales) {
        out.push((event_value(l, tables, m, w, v), sc));
    }
    let r = [v, -1.5 * v, 0.1 * v, 0.05 * v, 0.0];
    let g_end = event_value(l, tables, m, EventFn::Rest, -0.5 * v);
    out.push((
        locate_root(l, tables, m, EventFn::Rest, &r, g_end, 1e-13),
        1.0,
    ));
    out
}

/// The scale μ is made from: its own size, or on a table's piece the
/// sizes of its two terms, μ at the piece's lower point and the line's
/// rise from there (extended past the piece, they may cancel).
fn mu_scale(l: &Lane, tables: &[FrictionTable], branch: u32, mu: f64) -> f64 {
    let (lo, hi) = model::branch_edges(l, tables, branch);
    if l.friction != FrictionKind::Table || !(lo.is_finite() && hi.is_finite()) {
        return mu.abs();
    }
    let at_lo = model::mu_sliding(l, tables, lo, branch);
    at_lo.abs() + (mu - at_lo).abs()
}

/// The speeds each lane is tried at: rest, a hair off it, the laws'
/// branch speeds and the motor's synchronous speed (each side of them),
/// and spread values, both directions.
fn speeds(l: &Lane, tables: &[FrictionTable], u: &mut Uniforms) -> Vec<f64> {
    let mut v = vec![0.0, 1e-6, 1e-3, 0.5, 2.0, l.v_sync, 0.999 * l.v_sync];
    for b in edges(l, tables).into_iter().chain([model::AGMA_JUMP_M_S]) {
        let b = b / l.inv_cos_g;
        v.extend([0.9 * b, 1.1 * b]);
    }
    v.extend((0..4).map(|_| 6.0 * u.next()));
    v.iter().flat_map(|&x| [x, -x]).collect()
}

/// The finite sliding speeds where the lane's law changes branch.
fn edges(l: &Lane, tables: &[FrictionTable]) -> Vec<f64> {
    (0..branches(l, tables))
        .flat_map(|b| {
            let (lo, hi) = model::branch_edges(l, tables, b);
            [lo, hi]
        })
        .filter(|e| e.is_finite())
        .collect()
}

/// The branches a lane is tried on at sliding speed `vs`: both of a law
/// of two, else the speed's own and those beside it (a step is frozen on
/// a branch, and its stages reach past the branch's edges by a part of
/// a step, never to a far branch's speeds, where a table's line,
/// extended, can be far from the table).
fn tried(l: &Lane, tables: &[FrictionTable], vs: f64) -> Vec<u32> {
    let n = branches(l, tables);
    if n <= 2 {
        return (0..n).collect();
    }
    let b = model::branch_of(l, tables, vs);
    (b.saturating_sub(1)..=(b + 1).min(n - 1)).collect()
}

/// How many branches the lane's law has.
fn branches(l: &Lane, tables: &[FrictionTable]) -> u32 {
    let mut n = 1;
    while model::branch_edges(l, tables, n - 1).1.is_finite() {
        n += 1;
    }
    n
}

#[test]
fn the_shaders_model_functions_compute_what_the_rust_ones_do() {
    let tables =
        vec![FrictionTable::new(&[0.0, 0.1, 1.0, 5.0], &[0.08, 0.05, 0.04, 0.035]).unwrap()];
    let lanes = lanes(&tables);
    let mut u = Uniforms::new(5);
    let mut cases = Vec::new();
    let mut want = Vec::new();
    for (li, l) in lanes.iter().enumerate() {
        for v in speeds(l, &tables, &mut u) {
            let v32 = v as f32;
            // A table's line is read past rest (`mu_sliding`) only as far
            // as a step overshoots a rest: against the direction, a hair.
            let far_back = |f: u32| {
                let dir = if f & 2 != 0 { 1.0 } else { -1.0 };
                l.friction == FrictionKind::Table && dir * f64::from(v32) < -1e-3
            };
            let every = (0..8u32).filter(move |&f| !far_back(f)).flat_map(|f| {
                let vs = kernel::sliding_speed(
                    if f & 2 != 0 { 1.0 } else { -1.0 },
                    f64::from(v32),
                    l.inv_cos_g,
                );
                tried(l, &tables, vs).into_iter().map(move |b| f | b << 3)
            });
            for flags in every {
                let m = Mode {
                    side: if flags & 1 != 0 { 1 } else { -1 },
                    dir: if flags & 2 != 0 { 1 } else { -1 },
                    motor_on: flags & 4 != 0,
                    branch: flags >> 3,
                };
                // The case as the shader sees it: its speed in f32.
                cases.push([li as u32, v32.to_bits(), flags, 0]);
                want.push((li, m, f64::from(v32), cpu(l, &tables, m, f64::from(v32))));
            }
        }
    }
    let run = Run {
        entry: ENTRY,
        name: "mirrored",
        lanes: &lanes,
        tables: &tables,
        cases: &cases,
        args: &[],
        outs: K,
    };
    let Some(got) = values(&run) else {
        return;
    };
    let mut tally = Tally::new(NAMES.len());
    for (i, (li, m, v, w)) in want.iter().enumerate() {
        let l = &lanes[*li];
        // A decision is left to f32 where its quantity is within its reach
        // of the threshold: φ for the side, the sliding speed for the
        // branch, |T| against μs N for the stick.
        let n = (l.f2 * l.cos_g - w[16].0 * l.sin_g).abs();
        let near_side = w[14].0.abs() <= BOUND * w[14].1;
        let near_branch = edges(l, &tables)
            .iter()
            .any(|e| (w[3].0 - e).abs() <= BOUND * w[3].1);
        let near_stick = (w[21].0.abs() - l.mu_s * n).abs() <= BOUND * w[21].1;
        for (k, &(c, scale)) in w.iter().enumerate() {
            let near = match k {
                15 => near_side,
                17 => near_branch,
                _ => near_stick,
            };
            tally.add(k, f64::from(got[i * K + k]), c, scale, near, || {
                format!(
                    "{}: lane {li} ({:?}, {:?}), v {v:e}, {m:?}",
                    NAMES[k], l.friction, l.motor
                )
            });
        }
    }
    tally.report("mirrored model", &NAMES);
}
