//! Debug aid: one paper-design lane with load F2 run on CPU and GPU to
//! several end times. Usage: gpu_lanes F2 T1 T2 ...
use tswm::gpu::{Gpu, GpuBackend};
use tswm::integrator::Settings;
use tswm::params::{Num, Spec};
use tswm::runner::{Backend, CpuBackend};
fn main() {
    let a: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse().unwrap())
        .collect();
    let params: Vec<_> = a[1..]
        .iter()
        .map(|&t| {
            let mut s = Spec::default();
            s.set(Num::F2, a[0]);
            s.set(Num::TEnd, t);
            s.resolve(false).unwrap()
        })
        .collect();
    let mut g = GpuBackend::new(Gpu::new(false).unwrap(), Settings::default());
    g.gpu_mut().budget = std::env::var("BUDGET").map_or(64, |b| b.parse().unwrap());
    let mut c = CpuBackend::new(1, Settings::default()).unwrap();
    let (mut rg, mut rc) = (vec![], vec![]);
    g.run_chunk(0, &params, None, &mut rg).unwrap();
    c.run_chunk(0, &params, None, &mut rc).unwrap();
    for k in 0..params.len() {
        println!("{:?}\n{:?}", rc[k], rg[k]);
        println!(
            "t_end {}: cpu steps {} v {:.7} sw {} | gpu steps {} v {:.7} sw {} {}",
            a[k + 1],
            rc[k].steps,
            rc[k].v1_end,
            rc[k].switches,
            rg[k].steps,
            rg[k].v1_end,
            rg[k].switches,
            rg[k].status.name()
        );
    }
}
