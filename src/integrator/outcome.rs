//! The words of a lane's outcome: its final contact, what became of the
//! load of a lane whose motor is cut (`hold`), and what the motor achieved
//! in one whose motor runs (`drive`), docs/model.md sections 6 and 10.

/// Final contact state of a lane.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Contact {
    /// a-a: the worm pushes the wheel.
    Aa,
    /// b-b: the wheel pushes the worm.
    Bb,
    /// At rest, held by static friction.
    Stick,
}

impl Contact {
    /// Every final contact, in the order the tables list them.
    pub const ALL: [Contact; 3] = [Contact::Aa, Contact::Bb, Contact::Stick];

    /// The word of the results table.
    pub fn name(self) -> &'static str {
        match self {
            Contact::Aa => "aa",
            Contact::Bb => "bb",
            Contact::Stick => "stick",
        }
    }
}

/// What became of the load of a lane whose motor is cut before t_end
/// (docs/model.md section 10, "Does it hold?"): the `hold` column.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Hold {
    /// At rest and stuck: the drive holds the load with the motor off.
    Held,
    /// Sliding with the motor off and not slowing down: the load
    /// back-drives the gear and friction does not stop it.
    RunsAway,
    /// Sliding with the motor off and slowing down: not decided yet.
    Coasting,
}

impl Hold {
    /// Every outcome, in the order the tables list them.
    pub const ALL: [Hold; 3] = [Hold::Held, Hold::RunsAway, Hold::Coasting];

    /// The word of the results table.
    pub fn name(self) -> &'static str {
        match self {
            Hold::Held => "held",
            Hold::RunsAway => "runs_away",
            Hold::Coasting => "coasting",
        }
    }
}

/// What the motor achieved at the end of a lane whose motor runs to the
/// end (docs/model.md section 10, "Does the motor drive it?"): the `drive`
/// column. A motor-on lane at rest is stalled, never "held".
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Drive {
    /// Sliding in the motor's direction with the worm side feeding the
    /// mesh (p1 = S1 ẋ1 >= 0): the motor drives the load.
    Runs,
    /// Sliding in the motor's direction with the mesh driving the worm
    /// side (p1 < 0): the load overhauls and the motor brakes it.
    Overhauled,
    /// At rest and stuck: the motor cannot start (or keep moving) the load.
    Stalled,
    /// Sliding against the motor: the load drives the worm backwards.
    BackDriven,
}

impl Drive {
    /// Every outcome, in the order the tables list them.
    pub const ALL: [Drive; 4] = [
        Drive::Runs,
        Drive::Overhauled,
        Drive::Stalled,
        Drive::BackDriven,
    ];

    /// The word of the results table.
    pub fn name(self) -> &'static str {
        match self {
            Drive::Runs => "runs",
            Drive::Overhauled => "overhauled",
            Drive::Stalled => "stalled",
            Drive::BackDriven => "back_driven",
        }
    }
}

/// Which side of a searched parameter's critical value meets the
/// requirement (`[search]`): values below it, or values above it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Side {
    /// The requirement is met below the critical value.
    Below,
    /// The requirement is met above it.
    Above,
}

impl Side {
    /// Every side, in the order the tables list them.
    pub const ALL: [Side; 2] = [Side::Below, Side::Above];

    /// The word of the results table.
    pub fn name(self) -> &'static str {
        match self {
            Side::Below => "below",
            Side::Above => "above",
        }
    }
}

/// How a drive's search (`[search]`) ended: the `search_status` column.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum SearchStatus {
    /// The answer changes once; the critical value lies in a bracket no
    /// wider than `tol`.
    Found,
    /// The requirement is met at both ends of the bracket searched.
    MetAtBothEnds,
    /// The requirement is met at neither end.
    MetAtNeitherEnd,
    /// The first round saw the answer change more than once: the search
    /// assumes one change, so no critical value is given.
    SeveralChanges,
    /// A share boundary's search stopped refining the drive: its bracket
    /// lies clear of the boundary's, so it does not decide the answer
    /// (no critical value is given).
    StoppedClear,
}

impl SearchStatus {
    /// Every status, in the order the tables list them.
    pub const ALL: [SearchStatus; 5] = [
        SearchStatus::Found,
        SearchStatus::MetAtBothEnds,
        SearchStatus::MetAtNeitherEnd,
        SearchStatus::SeveralChanges,
        SearchStatus::StoppedClear,
    ];

    /// The word of the results table.
    pub fn name(self) -> &'static str {
        match self {
            SearchStatus::Found => "found",
            SearchStatus::MetAtBothEnds => "met_at_both_ends",
            SearchStatus::MetAtNeitherEnd => "met_at_neither_end",
            SearchStatus::SeveralChanges => "several_changes",
            SearchStatus::StoppedClear => "stopped_clear",
        }
    }
}

/// How a drive's search ended (`[search]`): its final bracket, which side
/// meets the requirement, its status and the lanes it integrated. The
/// row's other results are those of the lane at the bracket's end that
/// meets the requirement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SearchOutcome {
    /// The final bracket's lower end (the critical value lies in
    /// (lo, hi]).
    pub lo: f64,
    /// Its upper end.
    pub hi: f64,
    /// Which side meets the requirement (None: met at both ends, at
    /// neither, or the answer changes more than once).
    pub side: Option<Side>,
    /// How the search ended.
    pub status: SearchStatus,
    /// Lanes integrated for this drive.
    pub lanes: u32,
}

impl SearchOutcome {
    /// The critical value, the final bracket's middle, within half its
    /// width of the true one (NaN unless found).
    pub fn critical(&self) -> f64 {
        if self.status == SearchStatus::Found {
            0.5 * (self.lo + self.hi)
        } else {
            f64::NAN
        }
    }
}
