use tswm::integrator::*;
use tswm::model::*;
use tswm::params::*;
fn main() {
    {
        let tol: f64 = std::env::args().nth(1).map(|s| s.parse().unwrap()).unwrap_or(1e-9);
        let set = Settings { tol, ..Default::default() };
        let n = 20000;
        let lanes: Vec<Lane> = (0..n).map(|i| { let mut s = Spec::default(); let u = (i as f64 * 0.618034) % 1.0; s.set(Num::F2, -6000.0 + 12000.0 * u); Lane::new(&s.resolve(false).unwrap(), None) }).collect();
        let t0 = std::time::Instant::now();
        let mut acc = 0.0; let mut steps = 0u64;
        for l in &lanes { let r = simulate(l, None, &set); acc += r.x1_end; steps += r.steps as u64; }
        let dt = t0.elapsed().as_secs_f64();
        println!("{} lanes/s one thread, {:.1} steps/lane ({acc})", n as f64 / dt, steps as f64 / n as f64);
    }
    let cases: [(f64, Option<f64>, f64, f64); 5] = [(4774.0, None, 2.0, 0.1), (-4774.0, None, 2.0, 0.1), (-4774.0, Some(1.0), 5.0, 0.1), (-4774.0, Some(1.0), 5.0, 0.2), (-30000.0, None, 2.0, 0.1)];
    let exp = [(5.771091119655035,3.3957735036557426,2050.937580300045,2755.1189005233136,834.9727269735293),(5.028717801119965,3.254888376361646,7195.998937961469,-2400.709878254671,1146.8775679827304),(7.311565023880918,0.0,5006.106043181951,-3490.541142400748,1515.5649007798272),(1.0619302728932958,-1.601189693086556,3310.740433777799,-1013.9310245585192,1018.750905246571),(0.,0.,0.,0.,0.)];
    for tol in [tol_arg()] {
        let set = Settings { tol, ..Default::default() };
        let mut worst: f64 = 0.0; let mut steps = 0;
        for (i, c) in cases.iter().enumerate() {
            let mut s = Spec::default();
            s.set(Num::F2, c.0); if let Some(o) = c.1 { s.set(Num::MotorOff, o) } s.set(Num::TEnd, c.2); s.set(Num::GammaDeg, c.3.atan().to_degrees());
            let l = Lane::new(&s.resolve(false).unwrap(), None);
            let r = simulate(&l, None, &set);
            let e = exp[i];
            for (a, b) in [(r.x1_end, e.0), (r.v1_end, e.1), (r.w_motor, e.2), (r.w_load, e.3), (r.w_friction, e.4)] { worst = worst.max((a - b).abs() / b.abs().max(1.0)); }
            if i == 0 { worst = worst.max((r.t_first_switch - 0.48665342334234873).abs()); }
            steps += r.steps;
            if false { println!("{:?}", r); }
        }
        println!("tol {tol:e}: worst {worst:e}, steps {steps}");
    }
}
#[allow(dead_code)]
fn unused() {}

fn tol_arg() -> f64 { std::env::args().nth(1).map(|s| s.parse().unwrap()).unwrap_or(1e-9) }
