//! Where a row came from: the f64 path, the f32 path trusted, or the f64
//! path again (a GPU row not trusted, or a lane refined): the `path`
//! column.

/// Why a GPU row was not trusted and came from the f64 path instead.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Recheck {
    /// An input f32 cannot represent (sent to the CPU from the start).
    F32Range,
    /// The lane did not reach t_end within the dispatch budget.
    Unfinished,
    /// The GPU ended the lane with a status other than `ok`.
    GpuStatus,
    /// A result is not finite, or beyond what f32 resolves.
    NonFinite,
    /// The lane's own energy balance does not close within what f32 allows.
    EnergyBalance,
    /// A Kloss motor so stiff near synchronous speed that f32 cannot resolve its force.
    StiffMotor,
    /// A work that cancels below what f32 resolves of the energy that
    /// flowed (w_motor, w_load, and w_friction, whose integrand p1 + p2
    /// cancels where the mesh passes nearly all of its power).
    Cancellation,
    /// An efficiency (`eta_direct`, `eta_inverse`) whose two energies f32
    /// does not resolve to the trusted bound of their ratio, or whose
    /// emptiness (its input ≤ 1e-6 of the mesh's) f32 cannot decide.
    Efficiency,
    /// `hold` or `drive` turns on a sign at the end (of p1, of the
    /// acceleration, of the speed) that changes within the end speed's
    /// bound.
    EndSign,
    /// A step's p1, in a mode that does not decide its part (c·s = −1),
    /// turned and turned back inside it (the slope of its dense output at
    /// the step's middle against its ends): the split of that step's
    /// energy flow into in and out parts cannot be vouched for.
    FlowTurn,
    /// A switch ended a mode that a switch began before a step of it was
    /// accepted: the switching function grazed zero, and f32's rounding
    /// of it decides whether the lane stays in that mode, and the mode's
    /// share of the energy flow (a trusted row's w1_in read 0 for 0.038 J).
    SwitchGraze,
    /// A traced lane: its row comes from the f64 integration its trace is
    /// taken from, so the row and the trace are one integration.
    Traced,
}

impl Recheck {
    /// Every reason, in order.
    pub const ALL: [Recheck; 12] = [
        Recheck::F32Range,
        Recheck::Unfinished,
        Recheck::GpuStatus,
        Recheck::NonFinite,
        Recheck::EnergyBalance,
        Recheck::StiffMotor,
        Recheck::Cancellation,
        Recheck::Efficiency,
        Recheck::EndSign,
        Recheck::FlowTurn,
        Recheck::SwitchGraze,
        Recheck::Traced,
    ];

    /// The reason's word.
    pub fn name(self) -> &'static str {
        match self {
            Recheck::F32Range => "f32_range",
            Recheck::Unfinished => "unfinished",
            Recheck::GpuStatus => "gpu_status",
            Recheck::NonFinite => "nonfinite",
            Recheck::EnergyBalance => "energy_balance",
            Recheck::StiffMotor => "stiff_motor",
            Recheck::Cancellation => "cancellation",
            Recheck::Efficiency => "efficiency",
            Recheck::EndSign => "end_sign",
            Recheck::FlowTurn => "flow_turn",
            Recheck::SwitchGraze => "switch_graze",
            Recheck::Traced => "traced",
        }
    }
}

/// Which path a row came from: the `path` column of `lanes.csv`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum RowPath {
    /// The f64 CPU path (a CPU run).
    Cpu,
    /// The f32 GPU path, checked and trusted.
    Gpu,
    /// Computed on the GPU, not trusted, recomputed on the f64 path.
    Recomputed(Recheck),
    /// The f64 CPU path, run again at tighter settings because the lane's
    /// error estimate was over the bound (`accuracy`).
    Refined,
    /// The f64 GPU path (`--precision f64`): the CPU path's algorithm and
    /// bound, on the device.
    Gpu64,
}

impl RowPath {
    /// Every path, in code order: `cpu`, `gpu`, `cpu:refined`,
    /// `cpu:REASON` for each [`Recheck`] in its order, then `gpu64`.
    pub fn every() -> impl Iterator<Item = RowPath> {
        [RowPath::Cpu, RowPath::Gpu, RowPath::Refined]
            .into_iter()
            .chain(Recheck::ALL.map(RowPath::Recomputed))
            .chain([RowPath::Gpu64])
    }

    /// The path's code: its place in [`RowPath::every`] (the key of the
    /// `path` column's dictionary).
    pub fn code(self) -> usize {
        match self {
            RowPath::Cpu => 0,
            RowPath::Gpu => 1,
            RowPath::Refined => 2,
            RowPath::Recomputed(r) => 3 + r as usize,
            RowPath::Gpu64 => 3 + Recheck::ALL.len(),
        }
    }

    /// The cell: `cpu`, `gpu`, `cpu:refined`, `cpu:REASON` or `gpu64`.
    pub fn name(self) -> &'static str {
        RowPath::words()[self.code()]
    }

    /// The words of the `path` column in code order: each path spelt
    /// out once (a dozen words, kept for the run).
    pub fn words() -> &'static [&'static str] {
        static WORDS: std::sync::LazyLock<Vec<&'static str>> = std::sync::LazyLock::new(|| {
            RowPath::every()
                .map(|p| &*Box::leak(p.spelt().into_boxed_str()))
                .collect()
        });
        &WORDS
    }

    /// The cell spelt out.
    fn spelt(self) -> String {
        match self {
            RowPath::Cpu => "cpu".into(),
            RowPath::Gpu => "gpu".into(),
            RowPath::Recomputed(r) => format!("cpu:{}", r.name()),
            RowPath::Refined => "cpu:refined".into(),
            RowPath::Gpu64 => "gpu64".into(),
        }
    }
}
