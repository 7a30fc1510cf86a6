//! Errors. Bad input is one variant whose fields carry the file, the place
//! in it, the parameter and what is allowed, so `main` can print it on one
//! line and exit with code 2.

use std::path::{Path, PathBuf};

/// Everything `tswm` can fail with.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Bad input in a file (or on the command line): exit code 2.
    #[error("{}: {}{}{}", file.display(), at.as_deref().map(|a| format!("{a}: ")).unwrap_or_default(), param.as_deref().map(|p| format!("{p}: ")).unwrap_or_default(), msg)]
    Input {
        /// The file that holds the bad input.
        file: PathBuf,
        /// Where in it: "line 4", "row 3 (line 4)", "lane 17".
        at: Option<String>,
        /// The parameter or key concerned.
        param: Option<String>,
        /// What is wrong and what is allowed.
        msg: String,
    },
    /// A command line that names nothing to run, or conflicting options: exit code 2.
    #[error("{0}")]
    Usage(String),
    /// Reading or writing a file failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// The GPU backend failed (no adapter, device lost, out of memory).
    #[error("GPU: {0}")]
    Gpu(String),
    /// A worker thread died: a bug, never bad input.
    #[error("internal error: {0}")]
    Internal(String),
    /// `tswm check` found deviations beyond the bounds.
    #[error("check failed: {0}")]
    CheckFailed(String),
    /// The caller asked the command to stop (`progress::Watch::stop`);
    /// nothing was committed.
    #[error("stopped on request; nothing was written")]
    Stopped,
}

impl Error {
    /// Bad input in `file`. The parameter and message are made one line
    /// (control characters escaped, a long parameter cut), since they may
    /// quote the input.
    pub fn input(
        file: &Path,
        at: Option<String>,
        param: Option<&str>,
        msg: impl Into<String>,
    ) -> Error {
        Error::Input {
            file: file.to_path_buf(),
            at,
            param: param.map(|p| shown(p, 40)),
            msg: one_line(&msg.into()),
        }
    }

    /// An I/O error on `path`.
    pub fn io(path: &Path, source: std::io::Error) -> Error {
        Error::Io {
            path: path.to_path_buf(),
            source,
        }
    }

    /// The process exit code for this error.
    pub fn exit_code(&self) -> u8 {
        match self {
            Error::Input { .. } | Error::Usage(_) => 2,
            _ => 1,
        }
    }
}

/// Shorthand result.
pub type Result<T> = std::result::Result<T, Error>;

/// Text on one line: control characters escaped as `\n`, `\u{1}`, ...
pub fn one_line(s: &str) -> String {
    s.chars()
        .flat_map(|c| {
            if c.is_control() {
                c.escape_default().collect::<Vec<_>>()
            } else {
                vec![c]
            }
        })
        .collect()
}

/// Input quoted in a message: one line, at most `max` characters.
pub fn shown(s: &str, max: usize) -> String {
    let mut t = one_line(s);
    if t.chars().count() > max {
        t = t.chars().take(max).collect::<String>() + "...";
    }
    t
}

/// " (did you mean `m1`?)" when `name` is a near miss of one of
/// `candidates` (an edit or two away, or the same but for case), else "".
pub(crate) fn did_you_mean<'a>(
    name: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> String {
    let lower = name.to_ascii_lowercase();
    let best = candidates
        .into_iter()
        .map(|c| (edit_distance(&lower, &c.to_ascii_lowercase()), c))
        .min_by_key(|x| x.0);
    match best {
        Some((d, c)) if d <= (name.chars().count() / 3).max(2) && d < name.chars().count() => {
            format!(" (did you mean `{c}`?)")
        }
        _ => String::new(),
    }
}

/// Levenshtein distance (insertions, deletions, substitutions).
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != cb)).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn near_misses_are_named() {
        let names = ["m1", "m2", "gamma_deg", "t_end", "mu_static"];
        assert_eq!(
            did_you_mean("gama_deg", names),
            " (did you mean `gamma_deg`?)"
        );
        assert_eq!(did_you_mean("T_END", names), " (did you mean `t_end`?)");
        assert_eq!(did_you_mean("mass", names), "");
        assert_eq!(
            did_you_mean("mu_statik", names),
            " (did you mean `mu_static`?)"
        );
    }
}
