// Mirrors src/integrator/components.rs: the integrated state's components
// (x1, v1, w_motor, w_load, w_friction, w_p1).

// NY: generated into the prelude from src/integrator/components.rs.
