//! `report.html`: written for every shipped sweep, self-contained, markup
//! from the input escaped, rebuilt by `tswm report`, and rendered by a
//! real browser (headless Chromium).

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common::cpu;
use crate::common::{rejected, root, run_ok, tswm};

const SHIPPED: [&str; 6] = [
    "paper",
    "efficiency_map",
    "tolerance",
    "self_locking",
    "million",
    "heterogeneous",
];

/// Runs a shipped sweep on the CPU into `dir/o` and returns the report.
fn shipped_report(name: &str, dir: &Path) -> String {
    let sweep = root().join(format!("sweeps/{name}.toml"));
    run_ok(&cpu(&["run", sweep.to_str().unwrap(), "--out", "o"]), dir);
    std::fs::read_to_string(dir.join("o/report.html")).expect("report.html written")
}

/// Everything in a page that could fetch from elsewhere or run code.
fn external_references(html: &str) -> Vec<&'static str> {
    let lower = html.to_ascii_lowercase();
    [
        "http:", "https:", "//", "src=", "href=", "<link", "@import", "url(", "<script", "<iframe",
        "<img", "<object", "<embed", "<base", "srcset",
    ]
    .into_iter()
    .filter(|p| {
        // `//` also opens no reference inside text such as "a // b"; only
        // its use in an attribute or style counts.
        if *p == "//" {
            lower.contains("=\"//") || lower.contains("('//") || lower.contains("(\"//")
        } else {
            lower.contains(p)
        }
    })
    .collect()
}

#[test]
fn the_check_finds_an_external_reference() {
    // The check above is only worth something if it fails on a page that
    // fetches from elsewhere.
    for bad in [
        "<script src=\"https://cdn.example/x.js\"></script>",
        "<link rel=\"stylesheet\" href=\"a.css\">",
        "<style>@import url(//fonts.example/f.css);</style>",
        "<img src=\"data:image/png;base64,AA\">",
    ] {
        assert!(!external_references(bad).is_empty(), "{bad}");
    }
    assert!(external_references("<p>a/b, 1 // 2</p>").is_empty());
}

#[test]
fn markup_in_the_input_cannot_reach_the_page() {
    let dir = tempfile::tempdir().unwrap();
    let evil = "<script>alert(1)</script><img src=x onerror=alert(2)>";
    // A lane table whose file name is markup, under a sweep whose title is.
    let table = dir.path().join("<b onmouseover=alert(3)>lanes.csv");
    std::fs::write(&table, "gamma_deg,f2\n5.7,4774\n10,-4774\n").unwrap();
    std::fs::write(
        dir.path().join("s.toml"),
        format!("[base]\nt_end = 0.5\n[report]\ntitle = \"{evil}\"\n"),
    )
    .unwrap();
    run_ok(
        &cpu(&[
            "run",
            "s.toml",
            "--lanes",
            table.to_str().unwrap(),
            "--out",
            "o",
        ]),
        dir.path(),
    );
    let html = std::fs::read_to_string(dir.path().join("o/report.html")).unwrap();
    let lower = html.to_ascii_lowercase();
    for tag in ["<script", "<img", "<b "] {
        assert!(!lower.contains(tag), "{tag} reached the page");
    }
    assert!(html.contains("&lt;script&gt;alert(1)&lt;/script&gt;"));
    assert!(html.contains("&lt;b onmouseover=alert(3)&gt;lanes.csv"));
}

#[test]
fn tswm_report_rebuilds_the_report_from_the_folder() {
    let dir = tempfile::tempdir().unwrap();
    let first = shipped_report("tolerance", dir.path());
    std::fs::remove_file(dir.path().join("o/report.html")).unwrap();
    let out = tswm(&["report", "o"], dir.path());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        std::fs::read_to_string(dir.path().join("o/report.html")).unwrap(),
        first
    );
}

#[test]
fn no_report_writes_none_and_removes_an_old_one() {
    let dir = tempfile::tempdir().unwrap();
    shipped_report("paper", dir.path());
    let sweep = root().join("sweeps/paper.toml");
    let args = cpu(&["run", sweep.to_str().unwrap(), "--out", "o", "--no-report"]);
    run_ok(&args, dir.path());
    assert!(
        !dir.path().join("o/report.html").exists(),
        "an earlier run's report was left"
    );
}

#[test]
fn report_of_a_folder_without_a_run_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("empty")).unwrap();
    rejected(
        &["report", "empty"],
        dir.path(),
        &["sweep.resolved.toml", "tswm run"],
    );
}

#[test]
fn a_report_axis_off_the_grid_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("s.toml"),
        "[[grid]]\nparam = \"f2\"\nvalues = [1.0, 2.0]\n[report]\naxes = [\"m1\"]\n",
    )
    .unwrap();
    rejected(
        &["run", "s.toml", "--out", "o"],
        dir.path(),
        &["s.toml", "line", "report.axes", "allowed: f2"],
    );
    assert!(!dir.path().join("o").exists());
}

/// Debian's headless Chromium, if installed.
fn chromium() -> Option<PathBuf> {
    ["chromium-headless-shell", "chromium", "chromium-browser"]
        .iter()
        .map(|c| Path::new("/usr/bin").join(c))
        .find(|p| p.exists())
}

/// Share of pixels of a PNG that are not white.
fn inked_share(png_path: &Path) -> f64 {
    let f = std::io::BufReader::new(std::fs::File::open(png_path).unwrap());
    let mut rd = png::Decoder::new(f).read_info().unwrap();
    let mut buf = vec![0; rd.output_buffer_size().unwrap()];
    let info = rd.next_frame(&mut buf).unwrap();
    let px = info.color_type.samples();
    let data = &buf[..info.buffer_size()];
    let inked = data
        .chunks(px)
        .filter(|p| p.iter().take(3).any(|&c| c < 240))
        .count();
    inked as f64 / (data.len() / px) as f64
}

#[test]
fn every_shipped_sweep_gets_a_self_contained_report_that_renders() {
    let browser = chromium();
    if browser.is_none() {
        if std::env::var_os("CI").is_some() {
            panic!("CI: chromium-headless-shell is required (.ci/run installs it)");
        }
        crate::common::skipped(
            "rendering the reports",
            "no headless Chromium (apt-get install chromium-headless-shell)",
        );
    }
    for name in SHIPPED {
        let dir = tempfile::tempdir().unwrap();
        let html = shipped_report(name, dir.path());
        assert!(html.starts_with("<!DOCTYPE html>"), "{name}");
        assert_eq!(
            external_references(&html),
            Vec::<&str>::new(),
            "{name}: external reference"
        );
        assert!(html.contains("<svg"), "{name}: no figure");
        assert!(
            !html.contains("figure not drawn"),
            "{name}: a figure failed"
        );
        // What each kind of sweep shows.
        let want: &[&str] = match name {
            "paper" => &["Traces", "contact reactions", "force transfer function"],
            "efficiency_map" => &[
                "What was found",
                "Maps",
                "eta_direct_ss",
                "outcome (most lanes)",
                "static self-locking",
                "stalled",
                "Struck-through cells",
                "at rest left out (no running point)",
                "&lt;= 0: self-locking",
            ],
            "tolerance" => &[
                "Tolerance study",
                "what moves lock_margin_deg",
                "empirical CDF",
            ],
            "million" => &["Results against f2", "1000000 lanes"],
            "heterogeneous" => &["Tolerance study", "empirical CDF", "200000 lanes"],
            _ => &["Outcome against gamma_deg", ">held<", "Requirement"],
        };
        for w in want {
            assert!(html.contains(w), "{name}: no `{w}`");
        }
        if let Some(browser) = &browser {
            let share = render(
                browser,
                &dir.path().join("o/report.html"),
                &dir.path().join("shot.png"),
            );
            eprintln!(
                "{name}: {:.1} % of the first 1200x2400 px inked",
                100.0 * share
            );
            // A blank page is white; text, tables and figures ink several
            // per cent of it.
            assert!(share > 0.02, "{name}: the page renders blank ({share})");
        }
        // The million-lane folder is 400 MB: gone before the next sweep.
        drop(dir);
    }
}

/// Renders `page` to `shot` in headless Chromium; the share of inked
/// pixels.
fn render(browser: &Path, page: &Path, shot: &Path) -> f64 {
    let out = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
        ])
        .arg(format!("--screenshot={}", shot.display()))
        .arg("--window-size=1200,2400")
        .arg(format!("file://{}", page.display()))
        .output()
        .expect("run chromium");
    assert!(
        shot.exists(),
        "no screenshot: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    inked_share(shot)
}
