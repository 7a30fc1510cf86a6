use tswm::integrator::*;
use tswm::model::*;
use tswm::params::*;
fn main() {
    let l = Lane::new(&Spec::default().resolve(false).unwrap(), None);
    let set = Settings::default();
    let mut st = init(&l, None);
    let mut ts = vec![];
    while !advance(&l, None, &set, &mut st, 1) { ts.push(st.t); }
    let b = [1e-6,1e-5,1e-4,1e-3,1e-2,0.1,0.4,0.48,0.5,1.0,2.0];
    for w in b.windows(2) { println!("{:>8} - {:>8}: {}", w[0], w[1], ts.iter().filter(|&&t| t>w[0] && t<=w[1]).count()); }
    println!("total {}", ts.len());
}
