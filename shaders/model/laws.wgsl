// Mirrors src/model/laws.rs: the laws a lane may choose, as the codes
// `MotorKind::code` and `FrictionKind::code` give them.

const MOTOR_KLOSS: u32 = 0u;
const MOTOR_CONSTANT: u32 = 1u;
const FRICTION_PAPER: u32 = 0u;
const FRICTION_COULOMB: u32 = 1u;
const FRICTION_TABLE: u32 = 2u;
const FRICTION_AGMA: u32 = 3u;

// Whether the law's dρ/dVs is unbounded at rest (`FrictionKind::steep_at_rest`).
fn steep_at_rest(friction: u32) -> bool {
    return friction == FRICTION_PAPER || friction == FRICTION_AGMA;
}
