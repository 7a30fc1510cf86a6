use tswm::integrator::*;
use tswm::model::*;
fn main() {
    if let Ok(i) = std::env::var("SHOW") { show(i.parse().unwrap()); return; }
    let tol: f64 = std::env::args().nth(1).map(|s| s.parse().unwrap()).unwrap_or(1e-9);
    let specs = tswm::testmodels::random_user_lanes(3000, 11);
    let set = Settings { tol, ..Default::default() };
    let rset = Settings { tol: 1e-13, ..Default::default() };
    let mut nbad = 0; let mut worst = 0.0f64; let mut mism = 0; let mut wi = 0; let mut st = std::collections::BTreeMap::new();
    for (i, s) in specs.iter().enumerate() {
        let l = Lane::new(&s.resolve(false).unwrap(), None);
        let a = simulate(&l, None, &set); let b = simulate(&l, None, &rset);
        *st.entry(format!("{:?}/{:?}", b.status, b.contact_end)).or_insert(0) += 1;
        if (a.status, a.switches, a.reversals, a.sticks, a.contact_end) != (b.status, b.switches, b.reversals, b.sticks, b.contact_end) { mism += 1; continue; }
        let mut w = 0.0f64;
        for (x, y) in [(a.x1_end, b.x1_end), (a.v1_end, b.v1_end), (a.w_motor, b.w_motor), (a.w_load, b.w_load), (a.w_friction, b.w_friction)] { w = w.max((x - y).abs() / y.abs().max(1.0)); }
        if a.switches > 0 { w = w.max((a.t_first_switch - b.t_first_switch).abs()); }
        if w > 1e-6 { nbad += 1; } if w > worst { worst = w; wi = i; }
    }
    println!("tol {tol:e}: worst {worst:e} (lane {wi}), over 1e-6: {nbad}, discrete mismatches {mism}, {st:?}");
}
#[allow(dead_code)]
fn show(i: usize) {
    let specs = tswm::testmodels::random_user_lanes(3000, 11);
    let l = Lane::new(&specs[i].resolve(false).unwrap(), None);
    println!("{:?}\n{:?}", specs[i], l);
    for tol in [1e-9, 1e-11, 1e-13] { println!("{:?}", simulate(&l, None, &Settings { tol, ..Default::default() })); }
}
