//! Progress bars on stderr (shown only where asked, i.e. when stderr is a
//! terminal): the lanes of a run, and the check of a large sweep's lanes
//! before it.

/// A bar over `total` lanes, named by `what` ("" for the run's own);
/// hidden unless `show`.
pub fn bar(show: bool, total: u64, what: &str) -> indicatif::ProgressBar {
    let bar = if show {
        indicatif::ProgressBar::with_draw_target(
            Some(total),
            indicatif::ProgressDrawTarget::stderr(),
        )
    } else {
        indicatif::ProgressBar::hidden()
    };
    let prefix = if what.is_empty() {
        String::new()
    } else {
        format!("{what}: ")
    };
    bar.set_style(
        indicatif::ProgressStyle::with_template(&format!(
            "{prefix}{{bar:40}} {{pos}}/{{len}} lanes, {{per_sec}}, eta {{eta}}"
        ))
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar
}
