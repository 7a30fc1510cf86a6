//! The shipped cluster examples on real engines: a one-node Slurm
//! cluster (Debian's slurmctld, slurmd and munge, started here as root)
//! runs `examples/cluster/slurm.sbatch` as a job array and its dependent
//! merge; the Kubernetes Indexed Job's pod commands, read from the YAML
//! with a YAML parser, run with each `JOB_COMPLETION_INDEX`.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use crate::common::cpu;
use crate::common::{root, tswm};

/// Whether a command is on this machine.
fn have(cmd: &str) -> bool {
    Command::new("sh")
        .args(["-c", &format!("command -v {cmd}")])
        .stdout(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// Skips (printing why) or, in CI, fails when `why` holds.
fn skip_unless(ok: bool, why: &str) -> bool {
    if ok {
        return false;
    }
    if std::env::var_os("CI").is_some() {
        panic!("CI: {why} (.ci/run installs and runs it as root)");
    }
    crate::common::skipped("the cluster test", why);
    true
}

fn sh(cmd: &str) -> String {
    let o = Command::new("sh").args(["-c", cmd]).output().expect("sh");
    String::from_utf8_lossy(&o.stdout).trim().to_string()
}

/// The unsharded table of a sweep, for comparison.
fn unsharded(sweep: &Path, dir: &Path) -> Vec<u8> {
    let out = tswm(
        &cpu(&[
            "run",
            &sweep.display().to_string(),
            "--no-report",
            "--out",
            "single",
        ]),
        dir,
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    fs::read(dir.join("single/lanes.csv")).unwrap()
}

/// The daemons of a one-node Slurm cluster, stopped when dropped.
struct Slurm {
    conf: PathBuf,
    daemons: Vec<Child>,
    dir: PathBuf,
}

impl Drop for Slurm {
    fn drop(&mut self) {
        for d in &mut self.daemons {
            let _ = d.kill();
            let _ = d.wait();
        }
    }
}

impl Slurm {
    /// Starts munged (unless a munge daemon answers already), slurmctld
    /// and slurmd on this host, with state in `dir`, and waits for the
    /// node to be idle.
    fn start(dir: &Path) -> Slurm {
        if !Command::new("sh")
            .args(["-c", "munge -n | unmunge >/dev/null 2>&1"])
            .status()
            .is_ok_and(|s| s.success())
        {
            // munged runs as the munge user, with its socket folder.
            let st = Command::new("sh")
                .args([
                    "-c",
                    "mkdir -p /run/munge && chown munge:munge /run/munge && \
                     { [ -s /etc/munge/munge.key ] || runuser -u munge -- mungekey --create 2>/dev/null || \
                       { dd if=/dev/urandom of=/etc/munge/munge.key bs=1 count=1024 2>/dev/null && \
                         chown munge:munge /etc/munge/munge.key && chmod 400 /etc/munge/munge.key; }; } && \
                     runuser -u munge -- /usr/sbin/munged",
                ])
                .status()
                .expect("start munged");
            assert!(st.success(), "munged did not start");
        }
        let node = sh("slurmd -C | head -1");
        assert!(node.starts_with("NodeName="), "slurmd -C: {node}");
        let host = node
            .split_whitespace()
            .next()
            .unwrap()
            .trim_start_matches("NodeName=")
            .to_string();
        for d in ["state", "spool"] {
            fs::create_dir_all(dir.join(d)).unwrap();
        }
        let d = dir.display();
        // Ports of their own, so a cluster of the machine's is left alone.
        let conf = format!(
            "ClusterName=tswmtest\n\
             SlurmctldHost={host}(127.0.0.1)\n\
             SlurmctldPort=16817\n\
             SlurmdPort=16818\n\
             AuthType=auth/munge\n\
             SlurmUser=root\n\
             SlurmdUser=root\n\
             StateSaveLocation={d}/state\n\
             SlurmdSpoolDir={d}/spool\n\
             SlurmctldPidFile={d}/slurmctld.pid\n\
             SlurmdPidFile={d}/slurmd.pid\n\
             SlurmctldLogFile={d}/slurmctld.log\n\
             SlurmdLogFile={d}/slurmd.log\n\
             ProctrackType=proctrack/linuxproc\n\
             TaskPlugin=task/none\n\
             JobAcctGatherType=jobacct_gather/none\n\
             AccountingStorageType=accounting_storage/none\n\
             SelectType=select/cons_tres\n\
             SelectTypeParameters=CR_Core\n\
             MpiDefault=none\n\
             ReturnToService=2\n\
             {node} NodeAddr=127.0.0.1 State=UNKNOWN\n\
             PartitionName=tswm Nodes=ALL Default=YES MaxTime=INFINITE State=UP\n"
        );
        let conf_path = dir.join("slurm.conf");
        fs::write(&conf_path, conf).unwrap();
        let spawn = |prog: &str| {
            Command::new(prog)
                .args(["-D", "-f"])
                .arg(&conf_path)
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .unwrap_or_else(|e| panic!("{prog}: {e}"))
        };
        let mut s = Slurm {
            conf: conf_path.clone(),
            daemons: Vec::new(),
            dir: dir.to_path_buf(),
        };
        s.daemons.push(spawn("slurmctld"));
        s.daemons.push(spawn("slurmd"));
        let start = Instant::now();
        loop {
            let state = s.run("sinfo", &["-h", "-o", "%T"]);
            if state == "idle" {
                break;
            }
            assert!(
                start.elapsed() < Duration::from_secs(90),
                "the Slurm node is not idle after 90 s ({state}); logs in {}",
                s.dir.display()
            );
            std::thread::sleep(Duration::from_millis(500));
        }
        s
    }

    /// A Slurm client command against this cluster; its stdout.
    fn run(&self, prog: &str, args: &[&str]) -> String {
        let o = Command::new(prog)
            .args(args)
            .env("SLURM_CONF", &self.conf)
            .output()
            .unwrap_or_else(|e| panic!("{prog}: {e}"));
        String::from_utf8_lossy(&o.stdout).trim().to_string()
    }
}

#[test]
fn the_shipped_sbatch_script_runs_a_slurm_job_array_and_merges() {
    let is_root = sh("id -u") == "0";
    if skip_unless(
        is_root
            && ["slurmctld", "slurmd", "sbatch", "munged"]
                .iter()
                .all(|c| have(c)),
        "a one-node Slurm cluster needs root and slurmctld, slurmd, slurm-client and munge",
    ) {
        return;
    }
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    let slurm = Slurm::start(&dir.join("slurm"));
    let sweep = root().join("sweeps/tolerance.toml");
    let work = dir.join("work");
    let bin = PathBuf::from(env!("CARGO_BIN_EXE_tswm"));
    let out = Command::new("bash")
        .arg(root().join("examples/cluster/slurm.sbatch"))
        .arg(&sweep)
        .arg(&work)
        .arg("4")
        .env("SLURM_CONF", &slurm.conf)
        .env("TSWM", &bin)
        .current_dir(dir)
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(
        out.status.success(),
        "{said}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // "tswm: shards: job array A (4 tasks); merge: job M; ..."
    let job = |after: &str| -> String {
        said.split(after)
            .nth(1)
            .unwrap()
            .split(|c: char| !c.is_ascii_digit())
            .next()
            .unwrap()
            .to_string()
    };
    let (array, merge) = (job("job array "), job("merge: job "));
    let start = Instant::now();
    while !slurm.run("squeue", &["-h"]).is_empty() {
        assert!(
            start.elapsed() < Duration::from_secs(300),
            "jobs still queued after 300 s: {}",
            slurm.run("squeue", &[])
        );
        std::thread::sleep(Duration::from_millis(500));
    }
    // Every array task and the merge completed (scontrol remembers
    // finished jobs for MinJobAge, 300 s by default).
    let show = slurm.run("scontrol", &["show", "job", &array]);
    assert_eq!(show.matches("JobState=COMPLETED").count(), 4, "{show}");
    let show = slurm.run("scontrol", &["show", "job", &merge]);
    assert!(show.contains("JobState=COMPLETED"), "{show}");
    for k in 0..4 {
        assert!(
            work.join(format!("shard-{k}/shard.toml")).exists(),
            "shard {k}"
        );
    }
    let merged = fs::read(work.join("merged/lanes.csv")).expect("merged lanes.csv");
    assert!(
        merged == unsharded(&sweep, dir),
        "the merged lanes.csv differs from the unsharded one"
    );
    assert!(work.join("merged/report.html").exists());
}

/// The pod commands and shard counts of the shipped Kubernetes manifest,
/// read with a YAML parser (PyYAML): completions, the shard job's SHARDS
/// and command, the merge job's SHARDS and command.
fn k8s_manifest() -> Option<(u64, u64, String, u64, String)> {
    let py = "import sys, yaml\n\
              docs = list(yaml.safe_load_all(open(sys.argv[1])))\n\
              def pod(d):\n\
              \x20   c = d['spec']['template']['spec']['containers'][0]\n\
              \x20   env = {e['name']: e['value'] for e in c['env']}\n\
              \x20   assert c['command'] == ['/bin/sh', '-c'], c['command']\n\
              \x20   return env['SHARDS'], c['args'][0]\n\
              s, m = docs[0], docs[1]\n\
              assert s['spec']['completionMode'] == 'Indexed'\n\
              n, cmd = pod(s)\n\
              mn, mcmd = pod(m)\n\
              print(s['spec']['completions']); print(n); print(cmd); print(mn); print(mcmd)\n";
    let o = Command::new("/usr/bin/python3")
        .args(["-c", py])
        .arg(root().join("examples/cluster/k8s-indexed-job.yaml"))
        .output()
        .ok()?;
    if !o.status.success() {
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains("No module named 'yaml'"), "{err}");
        return None;
    }
    let text = String::from_utf8_lossy(&o.stdout).to_string();
    let l: Vec<&str> = text.lines().collect();
    Some((
        l[0].parse().unwrap(),
        l[1].parse().unwrap(),
        l[2].to_string(),
        l[3].parse().unwrap(),
        l[4].to_string(),
    ))
}

#[test]
fn the_kubernetes_indexed_job_maps_each_index_to_its_shard() {
    let Some((completions, shards, cmd, merge_shards, merge_cmd)) = k8s_manifest() else {
        skip_unless(false, "reading the Kubernetes manifest needs python3-yaml");
        return;
    };
    assert_eq!(shards, completions, "SHARDS must equal completions");
    assert_eq!(merge_shards, completions);
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    let sweep = root().join("sweeps/efficiency_map.toml");
    let bin = PathBuf::from(env!("CARGO_BIN_EXE_tswm"));
    let path = format!(
        "{}:{}",
        bin.parent().unwrap().display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let data = dir.join("data");
    fs::create_dir(&data).unwrap();
    // Each pod, as Kubernetes runs it: the index in JOB_COMPLETION_INDEX,
    // the env of the manifest (paths made local).
    let pod = |cmd: &str, index: Option<u64>| {
        let mut c = Command::new("/bin/sh");
        c.args(["-c", cmd])
            .env("PATH", &path)
            .env("SHARDS", shards.to_string())
            .env("SWEEP", &sweep)
            .env("DATA", &data);
        if let Some(i) = index {
            c.env("JOB_COMPLETION_INDEX", i.to_string());
        }
        let o = c.output().unwrap();
        assert!(
            o.status.success(),
            "{cmd}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        String::from_utf8_lossy(&o.stdout).to_string()
    };
    // Indices in any order, as pods start.
    for i in (0..completions).rev() {
        let said = pod(&cmd, Some(i));
        assert!(said.contains(&format!("shard {i}/{shards}")), "{said}");
        let m = fs::read_to_string(data.join(format!("shard-{i}/shard.toml"))).unwrap();
        assert!(
            m.contains(&format!("shard = {i}\n")) && m.contains(&format!("shards = {shards}\n")),
            "{m}"
        );
    }
    pod(&merge_cmd, None);
    let merged = fs::read(data.join("merged/lanes.csv")).unwrap();
    assert!(
        merged == unsharded(&sweep, dir),
        "the merged lanes.csv differs from the unsharded one"
    );
}
