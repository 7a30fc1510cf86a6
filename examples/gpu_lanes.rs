//! Debug aid: CPU vs GPU on chosen random user lanes (seed 31).
use tswm::gpu::{Gpu, GpuBackend};
use tswm::integrator::Settings;
use tswm::runner::{Backend, CpuBackend};
fn main() {
    let idx: Vec<usize> = std::env::args()
        .skip(1)
        .map(|a| a.parse().unwrap())
        .collect();
    let specs = tswm::testmodels::random_user_lanes(10_000, 31);
    let params: Vec<_> = idx
        .iter()
        .map(|&i| specs[i].resolve(false).unwrap())
        .collect();
    let mut g = GpuBackend::new(Gpu::new(false).unwrap(), Settings::default());
    let mut c = CpuBackend::new(1, Settings::default()).unwrap();
    let (mut rg, mut rc) = (vec![], vec![]);
    g.run_chunk(0, &params, None, &mut rg).unwrap();
    c.run_chunk(0, &params, None, &mut rc).unwrap();
    for k in 0..idx.len() {
        println!(
            "lane {}: {:?}\n  {:?}",
            idx[k],
            specs[idx[k]],
            tswm::model::Lane::new(&params[k], None)
        );
        println!("  cpu {:?}\n  gpu {:?}", rc[k], rg[k]);
    }
}
