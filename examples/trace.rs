use tswm::integrator::*;
use tswm::model::*;
fn run(l: &Lane, tol: f64, times: &[f64]) -> Vec<[f64; 5]> {
    let set = Settings { tol, ..Default::default() };
    let mut out = vec![];
    for &t in times {
        let mut l2 = *l; l2.t_end = t;
        let mut st = init(&l2, None);
        advance(&l2, None, &set, &mut st, u32::MAX);
        out.push(st.y);
    }
    out
}
fn main() {
    let specs = tswm::testmodels::random_user_lanes(3000, 11);
    let l = Lane::new(&specs[1749].resolve(false).unwrap(), None);
    let times = [0.001, 0.01, 0.05, 0.1, 0.3, 0.5, 0.7, 0.77, 0.79, 1.0, 1.3, 1.6251318680836992];
    let a = run(&l, 1e-9, &times); let b = run(&l, 1e-13, &times);
    for i in 0..times.len() { println!("t {:>6.3}: dv {:+.2e} dwm {:+.2e} dwl {:+.2e} wm {:.3}", times[i], a[i][1]-b[i][1], a[i][2]-b[i][2], a[i][3]-b[i][3], b[i][2]); }
}
