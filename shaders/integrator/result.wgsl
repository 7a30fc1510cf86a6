// Mirrors src/integrator/result.rs: how a lane ended.

// Status codes: keep in sync with `Status` in src/integrator/result.rs.
const S_OK: u32 = 0u;
const S_INCONSISTENT: u32 = 1u;
const S_NONFINITE: u32 = 2u;
const S_MAX_STEPS: u32 = 3u;
const S_MAX_EVENTS: u32 = 4u;
const S_STEP_UNDERFLOW: u32 = 5u;
