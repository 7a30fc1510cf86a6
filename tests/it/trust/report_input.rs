//! The report of any folder tswm can write, and of one whose table was
//! edited: a page or one error line, never a panic or a hang.

use super::*;

#[test]
fn a_2x2_coulomb_grid_over_f2_and_m1_gets_its_report() {
    let dir = tempfile::tempdir().unwrap();
    let html = report_of(
        dir.path(),
        "[base]\nfriction = \"coulomb\"\nmu = 0.05\nt_end = 0.5\n\
         [[grid]]\nparam = \"f2\"\nvalues = [-3000.0, 3000.0]\n\
         [[grid]]\nparam = \"m1\"\nvalues = [400.0, 800.0]\n",
    );
    assert!(html.contains("<svg") && !html.contains("figure not drawn"));
}

#[test]
fn a_grid_whose_cells_differ_by_1e_9_gets_its_report() {
    let dir = tempfile::tempdir().unwrap();
    let html = report_of(
        dir.path(),
        "[base]\nt_end = 0.3\n[[grid]]\nparam = \"f2\"\nvalues = [4774.0, 4774.000000001]\n\
         [[grid]]\nparam = \"m1\"\nvalues = [586.0, 586.000000001]\n",
    );
    assert!(html.contains("<svg") && !html.contains("figure not drawn"));
}

#[test]
fn extreme_but_allowed_parameters_get_their_report() {
    let dir = tempfile::tempdir().unwrap();
    let html = report_of(
        dir.path(),
        "[base]\nm1 = 1e9\nm2 = 1e9\nt_end = 1e5\n\
         [[grid]]\nparam = \"f2\"\nvalues = [-1000.0, 1000.0]\n\
         [[grid]]\nparam = \"gamma_deg\"\nvalues = [0.5, 85.0]\n",
    );
    assert!(html.contains("<svg") && !html.contains("figure not drawn"));
}

#[test]
fn a_cell_of_1e40_gets_a_report() {
    let dir = tempfile::tempdir().unwrap();
    report_of(dir.path(), SMALL);
    set_cell(dir.path(), 1, "w_friction", "1e40");
    set_cell(dir.path(), 2, "eta_direct", "-1e40");
    let out = report_within(dir.path(), 60);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_cell_of_1_7e308_does_not_hang_the_report() {
    let dir = tempfile::tempdir().unwrap();
    report_of(
        dir.path(),
        "[base]\nt_end = 0.3\n[[grid]]\nparam = \"f2\"\nvalues = [-3000.0, 0.0, 3000.0]\n",
    );
    set_cell(dir.path(), 0, "w_friction", "1.7e308");
    set_cell(dir.path(), 1, "w_friction", "-1.7e308");
    set_cell(dir.path(), 2, "eta_direct", "1.7976931348623157e308");
    let out = report_within(dir.path(), 60);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_lane_index_beyond_the_sweep_is_one_error_line() {
    let dir = tempfile::tempdir().unwrap();
    report_of(dir.path(), SMALL);
    set_cell(dir.path(), 3, "lane", "4000000");
    rejected(
        &["report", "o"],
        dir.path(),
        &["lanes.csv", "row 4", "lane"],
    );
}

/// The report reads only the columns it shows (a plotted result here);
/// a cell of one that is not a number is one error line. A column it does
/// not read is not parsed: the page cannot depend on it.
#[test]
fn text_in_a_number_cell_is_one_error_line() {
    let dir = tempfile::tempdir().unwrap();
    report_of(dir.path(), SMALL);
    set_cell(dir.path(), 2, "eta_direct_ss", "abc");
    rejected(
        &["report", "o"],
        dir.path(),
        &["lanes.csv", "row 3", "eta_direct_ss"],
    );
}

#[test]
fn a_table_cut_at_a_row_boundary_is_one_error_line() {
    let dir = tempfile::tempdir().unwrap();
    report_of(dir.path(), SMALL);
    let p = dir.path().join("o/lanes.csv");
    let text = std::fs::read_to_string(&p).unwrap();
    let keep: Vec<&str> = text.lines().take(3).collect();
    std::fs::write(&p, keep.join("\n") + "\n").unwrap();
    rejected(
        &["report", "o"],
        dir.path(),
        &["lanes.csv", "has 2 rows", "states 4 lanes"],
    );
}
