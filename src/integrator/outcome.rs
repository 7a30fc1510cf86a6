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
