//! The structure of `src/` as the maintainers' docs promise it: no file
//! over 400 lines and no function over 80 without a written reason, no
//! two modules that import each other (directly or through others), and
//! each result column's and output file's name spelled once.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use crate::common::root;

/// Every `.rs` file under `src/`, with its module path ("run::merge").
fn sources() -> Vec<(PathBuf, String)> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(p);
            }
        }
    }
    let src = root().join("src");
    let mut files = Vec::new();
    walk(&src, &mut files);
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let rel = p.strip_prefix(&src).unwrap().with_extension("");
            let mut parts: Vec<String> = rel
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect();
            if parts
                .last()
                .is_some_and(|l| l == "mod" || l == "lib" || l == "main")
            {
                parts.pop();
            }
            (p, parts.join("::"))
        })
        .collect()
}

/// A file's code before its test module (tests may use anything).
fn code(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    match text.find("#[cfg(test)]") {
        Some(i) => text[..i].to_string(),
        None => text,
    }
}

#[test]
fn no_file_over_400_lines_and_no_function_over_80_without_a_reason() {
    let mut bad = Vec::new();
    for (path, _) in sources() {
        let text = std::fs::read_to_string(&path).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let name = path.strip_prefix(root()).unwrap().display().to_string();
        if lines.len() > 400 && !text.contains("Why over 400 lines") {
            bad.push(format!("{name}: {} lines", lines.len()));
        }
        let code = code(&path);
        let lines: Vec<&str> = code.lines().collect();
        let mut i = 0;
        while i < lines.len() {
            let l = lines[i].trim_start();
            let is_fn = [
                "fn ",
                "pub fn ",
                "pub(crate) fn ",
                "pub(super) fn ",
                "const fn ",
            ]
            .iter()
            .any(|p| l.starts_with(p));
            if !is_fn {
                i += 1;
                continue;
            }
            // The body: from the first `{` to its match.
            let (mut depth, mut j, mut opened) = (0i32, i, false);
            'scan: while j < lines.len() {
                for ch in lines[j].chars() {
                    match ch {
                        '{' => {
                            depth += 1;
                            opened = true;
                        }
                        '}' => depth -= 1,
                        ';' if !opened => break 'scan,
                        _ => {}
                    }
                }
                if opened && depth == 0 {
                    break;
                }
                j += 1;
            }
            let len = j + 1 - i;
            let reason = lines[..i]
                .iter()
                .rev()
                .take_while(|l| {
                    l.trim_start().starts_with("//") || l.trim_start().starts_with("#[")
                })
                .any(|l| l.contains("Why over 80 lines"));
            if opened && len > 80 && !reason {
                bad.push(format!("{name}:{}: a function of {len} lines", i + 1));
            }
            i = if opened { j + 1 } else { i + 1 };
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}

/// Code without its comments: a doc link to another module
/// (`[advance](super::step::advance)`) names it for the reader and is
/// no import.
fn without_comments(code: &str) -> String {
    code.lines()
        .map(|l| match l.find("//") {
            // A `//` inside a string literal ("http://...") is rare in
            // this crate; cutting there only drops text, never adds an import.
            Some(i) => &l[..i],
            None => l,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The modules a file's code names: `crate::a::b` paths and `super::`
/// paths, resolved to the longest module path that exists.
fn imports(module: &str, code: &str, modules: &BTreeSet<String>) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let here: Vec<&str> = if module.is_empty() {
        Vec::new()
    } else {
        module.split("::").collect()
    };
    let ident = |c: char| c.is_alphanumeric() || c == '_' || c == ':';
    for (start, prefix) in [("crate::", ""), ("super::", "super")] {
        let mut from = 0;
        while let Some(i) = code[from..].find(start) {
            let at = from + i;
            from = at + start.len();
            if at > 0 && code[..at].ends_with(|c: char| c.is_alphanumeric() || c == '_' || c == ':')
            {
                continue;
            }
            let path: String = code[from..].chars().take_while(|&c| ident(c)).collect();
            let mut segs: Vec<String> = if prefix.is_empty() {
                Vec::new()
            } else {
                // `super` from a file module is its parent; a folder's
                // mod.rs is the folder itself.
                let mut p: Vec<String> = here.iter().map(|s| s.to_string()).collect();
                p.pop();
                p
            };
            let mut rest = path.as_str();
            while let Some(r) = rest.strip_prefix("super::") {
                segs.pop();
                rest = r;
            }
            segs.extend(
                rest.split("::")
                    .filter(|s| !s.is_empty())
                    .map(str::to_string),
            );
            while !segs.is_empty() && !modules.contains(&segs.join("::")) {
                segs.pop();
            }
            let target = segs.join("::");
            if !target.is_empty() && target != module {
                out.insert(target);
            }
        }
    }
    out
}

/// A cycle in `edges`, if there is one.
fn cycle(edges: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        n: &str,
        edges: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(n.to_string(), 1);
        stack.push(n.to_string());
        for m in edges.get(n).into_iter().flatten() {
            match state.get(m.as_str()) {
                Some(1) => {
                    let i = stack.iter().position(|s| s == m).unwrap();
                    let mut c = stack[i..].to_vec();
                    c.push(m.clone());
                    return Some(c);
                }
                Some(_) => {}
                None => {
                    if let Some(c) = visit(m, edges, state, stack) {
                        return Some(c);
                    }
                }
            }
        }
        stack.pop();
        state.insert(n.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for n in edges.keys() {
        if !state.contains_key(n) {
            if let Some(c) = visit(n, edges, &mut state, &mut Vec::new()) {
                return Some(c);
            }
        }
    }
    None
}

/// No two modules import each other, directly or through others: between
/// files (a folder's `mod.rs` holds its files, so its re-exports of them
/// are no import), and between the folders of `src/` (the stages).
#[test]
fn no_two_modules_import_each_other() {
    let files = sources();
    let modules: BTreeSet<String> = files.iter().map(|f| f.1.clone()).collect();
    let mut by_file: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut by_stage: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (path, module) in &files {
        if module.is_empty() {
            continue; // lib.rs and main.rs: the roots
        }
        let is_folder = path.file_name().is_some_and(|n| n == "mod.rs");
        let stage = module.split("::").next().unwrap().to_string();
        for t in imports(module, &without_comments(&code(path)), &modules) {
            let inside = t.starts_with(&format!("{module}::"));
            if !(is_folder && inside) {
                by_file.entry(module.clone()).or_default().insert(t.clone());
            }
            let ts = t.split("::").next().unwrap().to_string();
            if ts != stage {
                by_stage.entry(stage.clone()).or_default().insert(ts);
            }
        }
    }
    assert_eq!(cycle(&by_file), None, "modules that import each other");
    assert_eq!(cycle(&by_stage), None, "folders that import each other");
    // The check sees imports at all: the run stage imports the output one.
    assert!(by_stage["run"].contains("output"));
}

/// A result column's name is a string literal in `src/` once (its row of
/// the table of result columns); an output file's name once (`names`).
#[test]
fn each_column_and_file_name_is_spelled_once() {
    let code: Vec<(String, String)> = sources().into_iter().map(|(p, m)| (m, code(&p))).collect();
    let mut names: Vec<&str> = tswm::columns::results().iter().map(|c| c.name).collect();
    names.extend(tswm::output::names::RESULTS);
    names.extend([tswm::output::names::LOCK, tswm::output::names::MARKER]);
    let mut bad = Vec::new();
    for n in names {
        let lit = format!("\"{n}\"");
        let places: Vec<&str> = code
            .iter()
            .filter(|(_, c)| c.contains(&lit))
            .map(|(m, _)| m.as_str())
            .collect();
        let count: usize = code.iter().map(|(_, c)| c.matches(&lit).count()).sum();
        if count != 1 {
            bad.push(format!("{lit} {count} times: {places:?}"));
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}

/// How often `fn NAME` is defined (followed by `(` or `<`) in `text`.
fn definitions(text: &str, name: &str) -> usize {
    let pat = format!("fn {name}");
    text.match_indices(&pat)
        .filter(|(i, _)| {
            let before = text[..*i].chars().next_back();
            let after = text[i + pat.len()..].chars().next();
            !before.is_some_and(|c| c.is_alphanumeric() || c == '_')
                && matches!(after, Some('(') | Some('<'))
        })
        .count()
}

/// How often `fn NAME` is defined as a free function (at the start of a
/// line, with its visibility) in `text`.
fn free_definitions(text: &str, name: &str) -> usize {
    text.lines()
        .filter(|l| {
            let rest = ["pub fn ", "pub(crate) fn ", "pub(super) fn ", "fn "]
                .iter()
                .find_map(|p| l.strip_prefix(p));
            rest.and_then(|r| r.strip_prefix(name))
                .is_some_and(|r| r.starts_with('(') || r.starts_with('<'))
        })
        .count()
}

/// The model's kernel (the Kloss force, the paper law, φ, ψ, the sliding
/// speed, ...) is written once in `src/`, and the shader has a function
/// of each name; every helper the shader mirrors (the other friction
/// laws, the motion, the step's parts) is one function in `src/` and one
/// in the shader too.
#[test]
fn each_kernel_formula_is_written_once_and_mirrored_in_the_shader() {
    use tswm::backend::gpu::shader::{MIRRORED, SHADER};
    use tswm::model::kernel::KERNEL;
    let rust: String = sources()
        .iter()
        .map(|(p, _)| without_comments(&code(p)))
        .collect::<Vec<_>>()
        .join("\n");
    let wgsl = without_comments(&SHADER);
    let mut bad = Vec::new();
    for name in KERNEL {
        let n = definitions(&rust, name);
        if n != 1 {
            bad.push(format!(
                "kernel `{name}`: defined {n} times in src/, not once"
            ));
        }
    }
    for &name in KERNEL.iter().chain(MIRRORED) {
        // Once as a free function (the friction laws, φ, the motion, the
        // step's helpers; a W-lane struct's method may share the name),
        // or, where the twin is a method (a law enum's), once at all.
        let n = match free_definitions(&rust, name) {
            0 => definitions(&rust, name),
            free => free,
        };
        if n != 1 {
            bad.push(format!("`{name}`: defined {n} times in src/, not once"));
        }
        let n = definitions(&wgsl, name);
        if n != 1 {
            bad.push(format!(
                "`{name}`: defined {n} times in the shader, not once"
            ));
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}

/// The kernel's formulas are not restated inline: a line of code outside
/// `src/model/kernel.rs` that computes the Kloss slip, the paper law's ρ,
/// the load's term of φ, ψ's tangent sum or the sliding speed's clamp is
/// a second copy. (Each pattern finds every copy the code had before the
/// kernel was written once.)
#[test]
fn kernel_expressions_appear_only_in_the_kernel() {
    type Finds = fn(&str) -> bool;
    let copies: [(&str, Finds); 5] = [
        ("the Kloss slip (v_sync − v)/v_sync", |l| {
            l.contains("v_sync") && l.contains('-') && l.contains('/')
        }),
        ("the paper law's ρ = (π/180)/(a Vs^b + c)", |l| {
            l.contains("180.0") && l.contains("PI")
        }),
        ("φ's load term F2/(m2 tan γ)", |l| {
            l.contains("m2") && l.contains("tan_g") && l.contains("/ (")
        }),
        ("ψ's tangent sum 1 − tan γ t", |l| {
            l.contains("1.0 -") && l.contains("tan_g")
        }),
        ("the sliding speed max(s v, 0)/cos γ", |l| {
            l.contains(".max(0.0)") && l.contains("inv_cos_g")
        }),
    ];
    let mut bad = Vec::new();
    for (path, _) in sources() {
        if path.ends_with("model/kernel.rs") {
            continue;
        }
        let name = path.strip_prefix(root()).unwrap().display().to_string();
        for (n, line) in without_comments(&code(&path)).lines().enumerate() {
            for (what, finds) in copies {
                if finds(line) {
                    bad.push(format!("{name}:{}: {what}: {}", n + 1, line.trim()));
                }
            }
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}

/// Which components of a derivative the mesh powers are (p1 = k5,
/// p2 = k4 − k5) is said in one function, `powers`, in `src/` and in the
/// shader: no other line subtracts component 5 from component 4.
#[test]
fn the_mesh_powers_are_read_off_a_derivative_in_one_place() {
    use tswm::backend::gpu::shader::SHADER;
    let p2 = |l: &str| {
        let l: String = l.split_whitespace().collect();
        l.contains("[4]-") && l.contains("[5]") || l.contains("k4-k5")
    };
    let mut bad = Vec::new();
    for (path, _) in sources() {
        let name = path.strip_prefix(root()).unwrap().display().to_string();
        for (n, line) in without_comments(&code(&path)).lines().enumerate() {
            if p2(line) && !name.ends_with("integrator/components.rs") {
                bad.push(format!("{name}:{}: {}", n + 1, line.trim()));
            }
        }
    }
    let wgsl = without_comments(&SHADER);
    let in_shader: Vec<&str> = wgsl.lines().filter(|l| p2(l)).map(str::trim).collect();
    assert_eq!(
        in_shader,
        ["return vec2<real>(k5, k4 - k5);"],
        "the shader says p2 outside `powers`"
    );
    assert!(bad.is_empty(), "{bad:#?}");
}

/// Each shader file is listed once, exists, and names the Rust file it
/// mirrors, which exists.
#[test]
fn each_shader_file_names_the_rust_file_it_mirrors() {
    use tswm::backend::gpu::shader::SHADER_FILES;
    let mut on_disk: Vec<String> = Vec::new();
    for sub in ["model", "integrator"] {
        for e in std::fs::read_dir(root().join("shaders").join(sub)).unwrap() {
            let p = e.unwrap().path();
            on_disk.push(format!(
                "{sub}/{}",
                p.file_name().unwrap().to_string_lossy()
            ));
        }
    }
    on_disk.sort();
    let mut listed: Vec<String> = SHADER_FILES.iter().map(|s| s.to_string()).collect();
    listed.sort();
    assert_eq!(listed, on_disk, "shaders/ and SHADER_FILES differ");
    for f in SHADER_FILES {
        let text = std::fs::read_to_string(root().join("shaders").join(f)).unwrap();
        let first = text.lines().next().unwrap_or("");
        let rust = first
            .strip_prefix("// Mirrors ")
            .and_then(|r| r.split([':', ' ']).next())
            .unwrap_or_else(|| panic!("shaders/{f}: first line does not say what it mirrors"));
        assert!(
            root().join(rust).exists(),
            "shaders/{f} mirrors {rust}, which does not exist"
        );
    }
}

/// ARCHITECTURE.md's table of changes, first row: a friction law is its
/// declaration (`model::laws`) and the places that cannot be derived from
/// it, and each of those has it. Every law has its code in the shader's
/// generated prelude, an arm in the CPU's and the shader's `mu_sliding`,
/// at most `LAW_SLOTS` parameters, its word in docs/model.md section 5,
/// and a branch in the independent reference (but `table`, whose points a
/// lane's row does not carry).
#[test]
fn each_friction_law_is_in_every_place_its_declaration_cannot_reach() {
    use tswm::model::laws::LAW_SLOTS;
    use tswm::model::FrictionKind;
    use tswm::params::table::law_params;
    let prelude = tswm::backend::gpu::shader::prelude();
    let read = |p: &str| std::fs::read_to_string(root().join(p)).unwrap();
    let wgsl = without_comments(&read("shaders/model/friction.wgsl"));
    let rust = without_comments(&read("src/model/friction.rs"));
    let model = read("docs/model.md");
    let reference = read("tests/reference/scipy_reference.py");
    let mut bad = Vec::new();
    for k in FrictionKind::ALL {
        let name = k.name();
        let upper = name.to_uppercase();
        let variant = format!("{k:?}");
        let checks = [
            (
                "a code in the prelude",
                prelude.contains(&format!("const FRICTION_{upper}: u32 = {}u;", k.code())),
            ),
            (
                "an arm in the shader's mu_sliding",
                wgsl.contains(&format!("FRICTION_{upper}")),
            ),
            (
                "an arm in mu_sliding",
                rust.contains(&format!("FrictionKind::{variant} =>")),
            ),
            (
                "at most LAW_SLOTS parameters",
                law_params(k).len() <= LAW_SLOTS,
            ),
            (
                "its word in docs/model.md",
                model.contains(&format!("`{name}`")),
            ),
            (
                "a branch in scipy_reference.py",
                reference.contains(&format!("\"{name}\"")),
            ),
        ];
        for (what, ok) in checks {
            if !ok {
                bad.push(format!("{name}: no {what}"));
            }
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}
