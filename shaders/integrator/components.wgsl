// Mirrors src/integrator/components.rs: the integrated state's components
// (x1, v1, w_motor, w_load, w_friction, w_p1).

// Keep in sync with `NY` in src/integrator/components.rs.
const NY: u32 = 6u;
