//! The CPU path's vector widths: a lane's row is the same bits at every
//! width, on every instruction set this core has, whatever lanes share its
//! vector, in any order, on any number of threads and in chunks of any
//! size (docs/numerics.md, "Vector widths").

use std::path::Path;
use std::process::Command;

use crate::common::{read_csv, root};
use crate::reference::{python_for, script, Needs};
use tswm::input::testmodels::{paper_like, random_user_lanes};
use tswm::integrator::width::{isas, Width, LANES};
use tswm::integrator::{simulate, simulate_batch_at, LaneResult, Settings};
use tswm::model::{FrictionTable, Lane};
use tswm::params::{FrictionKind, Num, Spec, TableName};

/// Plain python3: the lane generator needs nothing else.
const PYTHON: Needs = Needs {
    modules: "csv",
    vars: &["TSWM_PYTHON"],
    install: "install python3",
};

/// Lanes of every law and start: random user lanes (paper and Coulomb,
/// motor cut-offs), some on a friction table, some under `agma` with a
/// flank angle, constant motors, initial speeds, running on to t_max.
fn mixed_lanes(n: usize) -> (Vec<Lane>, Vec<FrictionTable>) {
    let table = FrictionTable::new(&[0.0, 0.5, 2.0, 5.0], &[0.13, 0.07, 0.05, 0.04]).unwrap();
    let mut specs: Vec<Spec> = random_user_lanes(n, 22);
    specs.extend(paper_like(n / 4, 23));
    for (i, s) in specs.iter_mut().enumerate() {
        let unset_mu = |s: &mut Spec| {
            s.num[Num::Mu as usize] = None;
            s.num[Num::MuStatic as usize] = None;
        };
        match i % 7 {
            1 => {
                s.friction = Some(FrictionKind::Table);
                unset_mu(s);
            }
            2 => {
                s.friction = Some(FrictionKind::Agma);
                unset_mu(s);
                s.set(Num::AlphaNDeg, 5.0 + (i % 25) as f64);
            }
            _ => {}
        }
        if i % 3 == 0 {
            s.set(Num::V10, -2.0 + 0.013 * (i % 300) as f64);
        }
        if i % 4 == 0 && s.num[Num::MotorOff as usize].is_some() {
            s.set(Num::TMax, s.num[Num::TEnd as usize].unwrap_or(2.0) + 6.0);
        }
    }
    let names = [TableName::UNNAMED];
    let lanes = specs
        .iter()
        .map(|s| Lane::new(&s.resolve(&names).unwrap(), std::slice::from_ref(&table)))
        .collect();
    (lanes, vec![table])
}

/// Every field, to the bit (the Debug form of an f64 is its shortest
/// exact decimal).
fn bits(r: &[LaneResult]) -> Vec<String> {
    r.iter().map(|r| format!("{r:?}")).collect()
}

/// At every width and instruction set, in chunks of 1, 5, 64 and all
/// lanes, and with the lanes in another order, each lane's result is
/// `simulate`'s (one lane alone), bit for bit; and some lanes were
/// refined, stuck, switched and reversed, so every path was taken.
#[test]
fn every_width_order_and_chunk_gives_each_lane_the_same_bits() {
    let (lanes, tables) = mixed_lanes(400);
    let set = Settings::default();
    let alone: Vec<LaneResult> = lanes.iter().map(|l| simulate(l, &tables, &set)).collect();
    let want = bits(&alone);
    let n = lanes.len();
    // A fixed shuffle: i -> (i * 7919) mod n, n not a multiple of 7919.
    assert_ne!(n % 7919, 0);
    let perm: Vec<usize> = (0..n).map(|i| (i * 7919) % n).collect();
    let shuffled: Vec<Lane> = perm.iter().map(|&i| lanes[i]).collect();
    let mut tried = 0;
    for isa in isas() {
        for w in LANES {
            let width = Width { lanes: w, isa };
            for chunk in [1, 5, 64, n] {
                let mut out = alone.clone();
                for (l, o) in lanes.chunks(chunk).zip(out.chunks_mut(chunk)) {
                    simulate_batch_at(width, l, &tables, &set, o);
                }
                assert_eq!(bits(&out), want, "{} in chunks of {chunk}", width.name());
                tried += 1;
            }
            let mut out = alone.clone();
            simulate_batch_at(width, &shuffled, &tables, &set, &mut out);
            let back: Vec<LaneResult> = {
                let mut b = alone.clone();
                for (k, &i) in perm.iter().enumerate() {
                    b[i] = out[k];
                }
                b
            };
            assert_eq!(bits(&back), want, "{} shuffled", width.name());
        }
    }
    eprintln!("{tried} width, instruction set and chunk combinations, {n} lanes each");
    let count = |f: &dyn Fn(&LaneResult) -> bool| alone.iter().filter(|r| f(r)).count();
    assert!(count(&|r| r.path == tswm::integrator::RowPath::Refined) > 0);
    assert!(count(&|r| r.sticks > 0) > 0);
    assert!(count(&|r| r.switches > 0) > 0);
    assert!(count(&|r| r.reversals > 0) > 0);
    assert!(count(&|r| r.hold.is_some()) > 0);
}

/// Runs `tswm run --lanes TABLE` on the CPU at a forced width and thread
/// count into `dir/out`; its lanes.csv.
fn run_at(dir: &Path, table: &Path, width: &str, threads: &str, out: &str) -> Vec<Vec<String>> {
    let o = Command::new(env!("CARGO_BIN_EXE_tswm"))
        .args([
            "run",
            "--lanes",
            table.to_str().unwrap(),
            "--backend",
            "cpu",
        ])
        .args(["--threads", threads, "--no-report", "--out", out])
        .env("TSWM_SIMD_WIDTH", width)
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "{width} {threads}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    // The run says which width ran, in its provenance.
    let prov = std::fs::read_to_string(dir.join(out).join("sweep.resolved.toml")).unwrap();
    let w = tswm::integrator::width::parse(width).unwrap();
    assert!(prov.contains(&w.name()), "{width}: {prov}");
    read_csv(&dir.join(out).join("lanes.csv")).1
}

/// `lanes.csv` through the binary: byte-identical rows at widths 1, 2, 4,
/// 8 and 16, on 1 and 2 threads, and from the same lane table shuffled (rows
/// compared by lane), for the four recipes of the independent lane
/// generator (paper and Coulomb lanes; a wide recipe with constant
/// motors and initial speeds; lanes that run on to answer "does it
/// hold?"; `agma` lanes).
#[test]
fn lanes_csv_is_the_same_at_every_width_thread_count_and_order() {
    let Some(py) = python_for(&PYTHON, "lanes_csv_is_the_same_at_every_width") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let gen = root().join("tests/reference/random_lanes.py");
    for recipe in ["", "wide", "hold", "agma"] {
        let table = d.join(format!("in_{recipe}.csv"));
        let mut args = vec![
            gen.to_str().unwrap(),
            "150",
            "2222",
            table.to_str().unwrap(),
        ];
        if !recipe.is_empty() {
            args.push(recipe);
        }
        script(&py, &args);
        // The same table, rows in another order: row k holds lane perm[k].
        let text = std::fs::read_to_string(&table).unwrap();
        let mut lines: Vec<&str> = text.lines().collect();
        let header = lines.remove(0);
        let n = lines.len();
        let perm: Vec<usize> = (0..n).map(|k| (k * 37 + 11) % n).collect();
        assert_eq!(n % 37, 2); // 150 = 4·37 + 2: a permutation
        let shuffled = d.join(format!("shuffled_{recipe}.csv"));
        let body: Vec<&str> = perm.iter().map(|&i| lines[i]).collect();
        std::fs::write(&shuffled, format!("{header}\n{}\n", body.join("\n"))).unwrap();

        let want = run_at(d, &table, "1", "1", &format!("ref_{recipe}"));
        for width in LANES.map(|n| n.to_string()) {
            let width = width.as_str();
            for threads in ["1", "2"] {
                let got = run_at(
                    d,
                    &table,
                    width,
                    threads,
                    &format!("o_{recipe}_{width}_{threads}"),
                );
                assert_eq!(
                    got, want,
                    "recipe {recipe:?} width {width} threads {threads}"
                );
            }
            let got = run_at(d, &shuffled, width, "2", &format!("s_{recipe}_{width}"));
            let (h, _) = read_csv(&d.join(format!("ref_{recipe}/lanes.csv")));
            let lane = h.iter().position(|c| c == "lane").unwrap();
            // Rows compared without the lane index, which is the row's place.
            for (k, &i) in perm.iter().enumerate() {
                let (mut a, mut b) = (got[k].clone(), want[i].clone());
                assert_eq!(a[lane], k.to_string());
                a.remove(lane);
                b.remove(lane);
                assert_eq!(
                    a, b,
                    "recipe {recipe:?} width {width}: lane {i} shuffled to {k}"
                );
            }
        }
    }
}

/// A width the core cannot run, or a word that is none, is bad input: one
/// line naming the variable and what is allowed, exit 2, nothing written.
#[test]
fn a_forced_width_that_is_not_allowed_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let sweep = root().join("sweeps/paper.toml");
    for (bad, why) in [
        ("3", "allowed: 1, 2, 4, 8, 16"),
        ("wide", "allowed: 1, 2, 4, 8, 16"),
    ] {
        for args in [
            vec![
                "run",
                sweep.to_str().unwrap(),
                "--backend",
                "cpu",
                "--out",
                "o",
            ],
            vec!["devices"],
        ] {
            let o = Command::new(env!("CARGO_BIN_EXE_tswm"))
                .args(&args)
                .env("TSWM_SIMD_WIDTH", bad)
                .current_dir(d)
                .output()
                .unwrap();
            let err = String::from_utf8_lossy(&o.stderr);
            assert_eq!(o.status.code(), Some(2), "{bad} {args:?}: {err}");
            assert_eq!(err.trim_end().lines().count(), 1, "{err}");
            assert!(
                err.contains(&format!("TSWM_SIMD_WIDTH=\"{bad}\"")) && err.contains(why),
                "{err}"
            );
            assert!(!d.join("o").exists(), "{bad}: something was written");
        }
    }
}
