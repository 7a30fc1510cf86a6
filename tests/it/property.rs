//! The report on shapes, not on examples: 500 random sweeps (1 to 3 grid
//! axes of 1 to 4 values, equal and near-equal values, sampled or not,
//! extreme but allowed parameters, traces, requirements, the drive in gear
//! terms, every friction law, axes over words: laws and named friction
//! tables), each run on the
//! CPU path and its report built; then the folder's results are replaced
//! by values a folder can hold (constants, empty columns, huge and tiny
//! numbers, a trace with many events) and the report built again. Every
//! report must be a page: no panic, no error, no hang.

use std::path::Path;

use crate::common::{cpu, tswm};

use tswm::backend::Choice;
use tswm::cli::LanesArgs;
use tswm::cli::RunFlags;
use tswm::commands::run::run;

/// A fixed generator (xorshift): the same sweeps on every run.
pub(crate) struct Gen(pub(crate) u64);

impl Gen {
    pub(crate) fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    pub(crate) fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
    pub(crate) fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub(crate) fn pick<'a, T>(&mut self, v: &'a [T]) -> &'a T {
        &v[self.below(v.len() as u64) as usize]
    }
}

/// Values for a grid axis of `param`: random, equal, near-equal, or the
/// ends of the allowed range.
fn axis_values(g: &mut Gen, param: &str, n: usize) -> Vec<f64> {
    let (lo, hi) = match param {
        "gamma_deg" => (0.5, 85.0),
        "f2" => (-20000.0, 20000.0),
        "m1" | "m2" => (1e-3, 1e9),
        "mu" => (0.0, 1.0),
        "t_end" => (1e-3, 3.0),
        "v1_0" => (-100.0, 100.0),
        // Gear terms of a drive with d1 = 64 mm, z1 = 1, z2 = 40: lead
        // angles 0.5 to 38 deg, reduced masses within their range.
        "m_x" => (6e-4, 0.05),
        "t2" => (-600.0, 600.0),
        "j2" => (1.0, 1000.0),
        "n1_0" => (-1000.0, 1000.0),
        _ => (0.0, 1.0),
    };
    let base = lo + (hi - lo) * g.unit();
    (0..n)
        .map(|i| match g.below(5) {
            0 => base,
            1 => base * (1.0 + 1e-12 * i as f64),
            2 => *g.pick(&[lo, hi]),
            _ => lo + (hi - lo) * g.unit(),
        })
        .map(|v| {
            if param == "m1" || param == "m2" {
                v.max(1e-3)
            } else {
                v
            }
        })
        .collect()
}

/// A random sweep file and its lane count.
fn random_sweep(g: &mut Gen) -> (String, u64) {
    // 0: paper, 1: coulomb, 2: agma, 3: two named tables.
    let law = g.below(4);
    let coulomb = law == 1;
    let gear = g.below(4) == 0;
    let mut s = String::from("[base]\n");
    let t_end = *g.pick(&[0.05, 0.2, 0.5]);
    s += &format!("t_end = {t_end}\n");
    match law {
        1 => s += "friction = \"coulomb\"\nmu = 0.05\n",
        2 => s += &format!("friction = \"agma\"\nalpha_n_deg = {}\n", 40.0 * g.unit()),
        3 => s += "friction = \"table\"\n",
        _ => {}
    }
    if gear {
        // A drive in gear terms is given whole (its motor too).
        s += "d1 = 0.064\nz1 = 1\nz2 = 40\nm_x = 0.0064\nj1 = 0.6\nj2 = 168\nt2 = 300\n\
              n_sync = 1000\nn_crit = 600\nt_crit = 140\n";
    }
    if g.below(3) == 0 {
        s += &format!("motor_off = {}\n", t_end * g.unit());
        if g.below(2) == 0 {
            s += "t_max = 10.0\n";
        }
    }
    if g.below(8) == 0 && !gear {
        s += "m1 = 1e9\nm2 = 1e9\n";
    }
    let params: &[&str] = match (gear, coulomb) {
        (true, _) => &["m_x", "t2", "j2", "t_end", "n1_0"],
        (false, true) => &["gamma_deg", "f2", "m1", "mu", "t_end", "v1_0"],
        (false, false) => &["gamma_deg", "f2", "m1", "m2", "t_end", "v1_0"],
    };
    let axes = g.below(4) as usize;
    let mut used: Vec<&str> = Vec::new();
    let mut lanes = 1u64;
    // An axis over words: the two tables, or two laws without parameters
    // of their own.
    if law == 3 && g.below(2) == 0 {
        s += "[[grid]]\nparam = \"friction_table\"\nvalues = [\"bronze\", \"iron\"]\n";
        lanes *= 2;
    } else if law == 0 && g.below(3) == 0 {
        s += "[[grid]]\nparam = \"friction\"\nvalues = [\"paper\", \"agma\"]\n";
        lanes *= 2;
    } else if law == 3 {
        s += "friction_table = \"iron\"\n";
    }
    for _ in 0..axes {
        let p = *g.pick(params);
        if used.contains(&p) {
            continue;
        }
        used.push(p);
        let n = 1 + g.below(4) as usize;
        let v = axis_values(g, p, n);
        let list: Vec<String> = v.iter().map(|x| format!("{x:?}")).collect();
        s += &format!(
            "[[grid]]\nparam = \"{p}\"\nvalues = [{}]\n",
            list.join(", ")
        );
        lanes *= n as u64;
    }
    let sensitivity = g.below(4) == 0;
    if sensitivity {
        // A sensitivity design over one or two inputs: n (D + 2) lanes a
        // grid point.
        let n = 2 + g.below(5);
        let two = g.below(2) == 0;
        s += &format!(
            "[sensitivity]\nmethod = \"sobol\"\nn = {n}\nseed = {}\nbootstrap = {}\n\
             [[tolerance]]\nparam = \"{}\"\ndist = \"{}\"\ntol = {}\n",
            g.below(1000),
            g.pick(&[0, 10, 50]),
            if gear { "t2" } else { "f2" },
            g.pick(&["uniform", "normal", "triangular"]),
            *g.pick(&[0.0, 1.0, 2000.0])
        );
        if two {
            s += &format!(
                "[[tolerance]]\nparam = \"{}\"\ndist = \"uniform\"\ntol = 0.2\n",
                if gear { "j1" } else { "x1_0" }
            );
        }
        lanes *= n * if two { 4 } else { 3 };
    } else if g.below(2) == 0 {
        let n = 1 + g.below(6);
        s += &format!(
            "[sampling]\nmethod = \"{}\"\nn = {n}\nseed = {}\n\
             [[tolerance]]\nparam = \"{}\"\ndist = \"{}\"\ntol = {}\n",
            g.pick(&["monte_carlo", "latin_hypercube"]),
            g.below(1000),
            if gear { "t2" } else { "f2" },
            g.pick(&["uniform", "normal", "triangular"]),
            *g.pick(&[0.0, 1.0, 2000.0])
        );
        lanes *= n;
    }
    if g.below(3) == 0 {
        s += &format!("[trace]\nlanes = [0, {}]\ndt = 0.01\n", lanes - 1);
    }
    if law == 3 {
        s += "[friction_table.bronze]\nvs = [0, 0.5, 3]\nmu = [0.1, 0.06, 0.03]\n\
              [friction_table.iron]\nvs = [0, 2]\nmu = [0.15, 0.08]\n";
    }
    if g.below(3) == 0 && !sensitivity {
        let req = *g.pick(&[
            "hold = held",
            "contact_end = stick",
            "eta_direct >= 0.5",
            "status = ok",
        ]);
        s += &format!(
            "[report]\nrequire = \"{req}\"\nat_least = {}\nresults = [\"{}\", \"lock_margin_deg\"]\n",
            *g.pick(&[0.5, 0.99, 1.0]),
            g.pick(&["eta_direct", "eta_inverse", "w_friction", "steps", "t_stop"])
        );
    }
    (s, lanes)
}

/// Replaces the result cells of `dir/lanes.csv` by values a folder can
/// hold: a whole column constant, empty, huge, tiny or mixed.
fn odd_values(g: &mut Gen, dir: &Path) {
    let p = dir.join("lanes.csv");
    let text = std::fs::read_to_string(&p).unwrap();
    let mut lines: Vec<Vec<String>> = text
        .lines()
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    let head = lines[0].clone();
    for name in [
        "eta_direct",
        "eta_inverse",
        "w_friction",
        "lock_margin_deg",
        "x1_end",
        "steps",
        "t_stop",
    ] {
        let i = head.iter().position(|h| h == name).unwrap();
        let kind = g.below(6);
        for row in lines.iter_mut().skip(1) {
            row[i] = match (kind, name) {
                (_, "steps") => g.below(1 << 40).to_string(),
                (0, _) => "".into(),
                (1, _) => "4774.0".into(),
                (2, _) => format!("{:?}", *g.pick(&[1.7e308, -1.7e308, f64::MAX, f64::MIN])),
                (3, _) => format!("{:?}", *g.pick(&[5e-324, -1e-300, 1e40, -1e40])),
                (4, _) => format!("{:?}", 4774.0 + 1e-9 * g.unit()),
                _ => continue,
            };
        }
    }
    let out: Vec<String> = lines.iter().map(|r| r.join(",")).collect();
    std::fs::write(&p, out.join("\n") + "\n").unwrap();
    // A traced lane's rows replaced by one with thousands of events.
    let t = dir.join("traces.csv");
    if t.exists() && g.below(2) == 0 {
        let mut s = String::from("lane,t,x1,v1,a1,f1,s1,s2,psi,phi,contact\n");
        for i in 0..6000 {
            let time = i as f64 * 1e-5;
            s += &format!("0,{time},0,{},0,0,1e308,-1e308,,0,stick\n", i % 3);
            s += &format!("0,{time},0,0,0,0,0,0,-0.1,0,aa\n");
        }
        std::fs::write(&t, s).unwrap();
    }
}

#[test]
fn five_hundred_random_sweeps_get_their_reports() {
    let mut g = Gen(0x2545_F491_4F6C_DD1D);
    let root = tempfile::tempdir().unwrap();
    for case in 0..500 {
        let (text, _) = random_sweep(&mut g);
        let dir = root.path().join(format!("c{case}"));
        std::fs::create_dir(&dir).unwrap();
        let sweep = dir.join("s.toml");
        std::fs::write(&sweep, &text).unwrap();
        let lanes = LanesArgs {
            sweep: Some(sweep),
            lanes: None,
            threads: Some(1),
            tol: None,
            precision: tswm::backend::Precision::Auto,
        };
        let out = dir.join("o");
        let flags = RunFlags {
            out: out.clone(),
            backend: Choice::Cpu,
            trace: Vec::new(),
            trace_dt: None,
            no_report: false,
            shard: None,
            format: tswm::output::table::Format::Csv,
            dry_run: false,
        };
        run(&lanes, &flags, &Default::default())
            .unwrap_or_else(|e| panic!("case {case}: {e}\n{text}"));
        odd_values(&mut g, &out);
        let page = tswm::report::build(&out).unwrap_or_else(|e| panic!("case {case}: {e}\n{text}"));
        assert!(!page.contains("figure not drawn"), "case {case}\n{text}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

/// A random sweep with axes over laws, motors and tables, whose `[base]`
/// sets parameters owned by several of the laws.
fn random_word_sweep(g: &mut Gen) -> String {
    let mut s = String::from("[base]\nt_end = 0.05\n");
    let laws = ["paper", "coulomb", "table", "agma"];
    let mut on: Vec<&str> = laws.iter().copied().filter(|_| g.below(2) == 0).collect();
    if on.is_empty() {
        on.push(*g.pick(&laws));
    }
    let has = |l: &str| on.contains(&l);
    if has("coulomb") {
        s += &format!("mu = {}\n", 0.01 + 0.2 * g.unit());
        if g.below(2) == 0 {
            s += "mu_static = 0.25\n";
        }
    }
    if has("paper") && g.below(2) == 0 {
        s += &format!("fric_c = {}\n", 0.1 + 0.1 * g.unit());
    }
    if (has("coulomb") || has("table") || has("agma")) && g.below(2) == 0 {
        s += &format!("alpha_n_deg = {}\n", 30.0 * g.unit());
    }
    let motors = g.below(3);
    if motors > 0 {
        s += &format!("f1 = {}\n", 500.0 + 3000.0 * g.unit());
        if motors == 2 && g.below(2) == 0 {
            s += "v_sync = 3.0\n";
        }
    }
    s += &format!(
        "gamma_deg = {}\nf2 = {}\n",
        2.0 + 30.0 * g.unit(),
        -8000.0 + 16000.0 * g.unit()
    );
    let list = |w: &[&str]| {
        w.iter()
            .map(|x| format!("\"{x}\""))
            .collect::<Vec<_>>()
            .join(", ")
    };
    if on.len() > 1 || g.below(2) == 0 {
        s += &format!("[[grid]]\nparam = \"friction\"\nvalues = [{}]\n", list(&on));
    } else {
        s += &format!("friction = \"{}\"\n", on[0]);
    }
    if motors == 2 {
        s += "[[grid]]\nparam = \"motor\"\nvalues = [\"constant\", \"kloss\"]\n";
    } else if motors == 1 {
        s = s.replacen("[base]\n", "[base]\nmotor = \"constant\"\n", 1);
    }
    if has("table") {
        s += "[[grid]]\nparam = \"friction_table\"\nvalues = [\"bronze\", \"iron\"]\n";
        s += "[friction_table.bronze]\nvs = [0.0, 1.0]\nmu = [0.1, 0.05]\n";
        s += "[friction_table.iron]\nvs = [0.0, 1.0]\nmu = [0.16, 0.08]\n";
    }
    s
}

/// Word axes over laws and motors run, each lane taking the parameters
/// its own law uses, and a run's `sweep.resolved.toml` always runs again
/// to the same lanes, byte for byte.
#[test]
fn sweeps_with_word_axes_run_and_their_resolved_sweeps_give_the_same_lanes() {
    let mut g = Gen(0x9E37_79B9_7F4A_7C15);
    let dir = tempfile::tempdir().unwrap();
    for case in 0..80 {
        let text = random_word_sweep(&mut g);
        let d = dir.path().join(format!("c{case}"));
        std::fs::create_dir(&d).unwrap();
        std::fs::write(d.join("s.toml"), &text).unwrap();
        let out = tswm(&cpu(&["run", "s.toml", "--out", "o", "--no-report"]), &d);
        assert!(
            out.status.success(),
            "case {case}: {}\n{text}",
            String::from_utf8_lossy(&out.stderr)
        );
        let again = tswm(
            &cpu(&["run", "o/sweep.resolved.toml", "--out", "o2", "--no-report"]),
            &d,
        );
        assert!(
            again.status.success(),
            "case {case}: the resolved sweep: {}\n{}",
            String::from_utf8_lossy(&again.stderr),
            std::fs::read_to_string(d.join("o/sweep.resolved.toml")).unwrap()
        );
        assert_eq!(
            std::fs::read(d.join("o/lanes.csv")).unwrap(),
            std::fs::read(d.join("o2/lanes.csv")).unwrap(),
            "case {case}:\n{text}"
        );
    }
}
