//! docs/model.md section 10, "Does the motor drive it?": the `drive`
//! column and the starting efficiencies, lane by lane against the model's
//! definitions computed here from each row's own cells, on random
//! motor-on and motor-cut lanes of every law, on the CPU and the GPU; and
//! no word of a report calls a motor-on lane "held".

use crate::common::*;
use crate::property::Gen;

/// μs as the model defines it for the lane's law, from its row: μs (or μ)
/// for coulomb, 0.150 for agma, the table's μ at rest for table, and for
/// the paper's law tan ρ(0) with ρ(0) = 1/c degrees.
fn rho_s(h: &[String], r: &[String], table_mu0: f64) -> f64 {
    let num = |k: &str| col(h, r, k).parse::<f64>().unwrap_or(f64::NAN);
    let an = match num("alpha_n_deg") {
        a if a.is_nan() => 0.0,
        a => a.to_radians(),
    };
    match col(h, r, "friction") {
        "paper" => (1.0 / num("fric_c")).to_radians(),
        "coulomb" => (num("mu_static") / an.cos()).atan(),
        "agma" => (0.150 / an.cos()).atan(),
        "table" => (table_mu0 / an.cos()).atan(),
        f => panic!("law {f}"),
    }
}

/// A random lane table: motors kloss and constant (f1 of either sign, or
/// 0), every friction law, motors cut or not, loads that run, stall and
/// back-drive.
fn lanes(n: usize, seed: u64) -> String {
    let mut g = Gen(seed);
    let mut s =
        String::from("gamma_deg,f2,motor,f1,friction,mu,alpha_n_deg,motor_off,t_end,t_max,v1_0\n");
    for _ in 0..n {
        let gamma = 2.0 + 38.0 * g.unit();
        let f2 = -30000.0 + 60000.0 * g.unit();
        let (motor, f1) = match g.below(4) {
            0 => ("constant", *g.pick(&[-3000.0, 0.0, 800.0, 3000.0])),
            _ => ("kloss", f64::NAN),
        };
        let friction = *g.pick(&["paper", "coulomb", "agma", "table"]);
        let mu = if friction == "coulomb" {
            0.01 + 0.3 * g.unit()
        } else {
            f64::NAN
        };
        let an = if friction == "paper" {
            f64::NAN
        } else {
            25.0 * g.unit()
        };
        let t_end = 0.5;
        let (off, t_max) = match g.below(3) {
            0 => (0.4 * g.unit(), 3.0),
            1 => (1.0, f64::NAN),
            _ => (f64::NAN, f64::NAN),
        };
        let v10 = if g.below(4) == 0 {
            2.0 * g.unit() - 1.0
        } else {
            0.0
        };
        let cell = |v: f64| {
            if v.is_nan() {
                String::new()
            } else {
                format!("{v}")
            }
        };
        s += &format!(
            "{gamma},{f2},{motor},{},{friction},{},{},{},{t_end},{},{v10}\n",
            cell(f1),
            cell(mu),
            cell(an),
            cell(off),
            cell(t_max)
        );
    }
    s
}

const TABLE: &str = "[friction_table]\nvs = [0.0, 0.5, 2.0]\nmu = [0.11, 0.06, 0.04]\n";

/// Checks every row of `dir/o/lanes.csv` against section 10; returns how
/// many lanes had each drive word.
fn check_rows(h: &[String], rows: &[Vec<String>]) -> [usize; 5] {
    let mut seen = [0usize; 5];
    for r in rows {
        let lane = col(h, r, "lane");
        let num = |k: &str| col(h, r, k).parse::<f64>().unwrap_or(f64::NAN);
        let drive = col(h, r, "drive");
        if col(h, r, "status") != "ok" {
            assert_eq!(drive, "", "lane {lane}: not ok, no drive");
            continue;
        }
        let cut = num("motor_off") < num("t_end");
        let dir = match col(h, r, "motor") {
            "kloss" => 1.0,
            _ => num("f1").signum() * (num("f1") != 0.0) as i32 as f64,
        };
        // In the motor's direction, p1 = S1 v1 = psi S2 v1 has the sign of
        // c s tan(gamma + c s rho) (S2 = -m1 m2 tan(gamma) phi / D, c =
        // sign(phi), D > 0; sections 2 and 3): p1 < 0, overhauled, exactly
        // when c s = -1 and gamma > rho(Vs_end), i.e. eta_inverse_ss > 0.
        let c = match col(h, r, "contact_end") {
            "aa" => 1.0,
            _ => -1.0,
        };
        let s = num("v1_end").signum();
        let want = if cut || dir == 0.0 {
            ""
        } else if col(h, r, "contact_end") == "stick" {
            "stalled"
        } else if s != dir {
            "back_driven"
        } else if c * s < 0.0 && num("eta_inverse_ss") > 0.0 {
            "overhauled"
        } else {
            "runs"
        };
        assert_eq!(drive, want, "lane {lane}: {r:?}");
        seen[["", "runs", "overhauled", "stalled", "back_driven"]
            .iter()
            .position(|w| *w == drive)
            .unwrap()] += 1;
        // A motor-on lane is never "held": hold is the motor-cut lanes'.
        assert_eq!(col(h, r, "hold").is_empty(), !cut, "lane {lane}");
        let g = num("gamma_deg").to_radians();
        let rs = rho_s(h, r, 0.11);
        for (name, want) in [
            ("eta_direct_start", g.tan() / (g + rs).tan()),
            ("eta_inverse_start", (g - rs).tan() / g.tan()),
            ("lock_margin_deg", (rs - g).to_degrees()),
        ] {
            let got = num(name);
            assert!(
                (got - want).abs() <= 1e-12 * want.abs().max(1.0),
                "lane {lane} {name}: {got} vs {want}"
            );
        }
        // <= 0 exactly when statically self-locking.
        assert_eq!(
            num("eta_inverse_start") <= 0.0,
            num("lock_margin_deg") >= 0.0,
            "lane {lane}"
        );
    }
    seen
}

#[test]
fn drive_and_the_starting_efficiencies_follow_the_model_on_every_lane() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("l.csv"), lanes(400, 0x5eed)).unwrap();
    std::fs::write(dir.path().join("t.toml"), TABLE).unwrap();
    let args = ["run", "--lanes", "l.csv", "t.toml", "--out", "o"];
    let (_, h, rows) = run_ok(&cpu(&args), dir.path());
    let seen = check_rows(&h, &rows);
    // Every word occurs, and lanes without a drive (cut, or no motor).
    assert!(seen.iter().all(|&k| k > 0), "{seen:?}");
    // The GPU's rows give the same words (its end state, the same
    // conversion to a row).
    if no_gpu("drive on the GPU") {
        return;
    }
    let mut gpu = args.to_vec();
    gpu[5] = "g";
    gpu.extend(["--backend", "gpu"]);
    let out = tswm(&gpu, dir.path());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (gh, grows) = read_csv(&dir.path().join("g/lanes.csv"));
    check_rows(&gh, &grows);
    for (c, g) in rows.iter().zip(&grows) {
        if col(&h, c, "status") == "ok" && col(&gh, g, "status") == "ok" {
            assert_eq!(col(&h, c, "drive"), col(&gh, g, "drive"), "{c:?}");
        }
    }
}

/// The section 7 cases: case 1 is overhauled (after its switch the load
/// overhauls and the motor brakes above synchronous speed), case 2 runs, the
/// stall is stalled from t = 0, the hold and back-drive lanes have their
/// motor cut (no drive).
#[test]
fn the_reference_cases_drive_as_the_model_says() {
    let dir = tempfile::tempdir().unwrap();
    let (h, rows) = run_fixture_lanes(dir.path());
    let drives: Vec<&str> = rows.iter().map(|r| col(&h, r, "drive")).collect();
    assert_eq!(drives, ["overhauled", "runs", "", "", "stalled"]);
}

/// A report of motor-on lanes that stall says "stalled", and no chart or
/// table word calls them "held".
#[test]
fn a_report_of_stalled_lanes_says_stalled_never_held() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("s.toml"),
        "[base]\nfriction = \"coulomb\"\nf2 = -8000.0\nt_end = 1.0\n\
         [[grid]]\nparam = \"gamma_deg\"\nfrom = 2.0\nto = 30.0\nn = 8\n\
         [[grid]]\nparam = \"mu\"\nvalues = [0.02, 0.15]\n",
    )
    .unwrap();
    let (_, h, rows) = run_ok(&cpu(&["run", "s.toml", "--out", "o"]), dir.path());
    let stalled = rows
        .iter()
        .filter(|r| col(&h, r, "drive") == "stalled")
        .count();
    assert!(stalled > 0, "the sweep has stalls");
    let html = std::fs::read_to_string(dir.path().join("o/report.html")).unwrap();
    assert!(html.contains(&format!(
        "{stalled} of {} finished lanes are stalled",
        rows.len()
    )));
    assert!(html.contains(">stalled<"), "the outcome legend names them");
    for bad in [">held<", "stick (held)", "(held)"] {
        assert!(!html.contains(bad), "`{bad}` in a report of motor-on lanes");
    }
    // The line along gamma of the same lanes: its outcome chart too.
    std::fs::write(
        dir.path().join("l.toml"),
        "[base]\nfriction = \"coulomb\"\nmu = 0.15\nf2 = -8000.0\nt_end = 1.0\n\
         [[grid]]\nparam = \"gamma_deg\"\nfrom = 2.0\nto = 30.0\nn = 20\n",
    )
    .unwrap();
    run_ok(&cpu(&["run", "l.toml", "--out", "o2"]), dir.path());
    let html = std::fs::read_to_string(dir.path().join("o2/report.html")).unwrap();
    assert!(html.contains(">stalled<") && !html.contains(">held<"));
}
