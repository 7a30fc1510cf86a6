// Mirrors src/integrator/components.rs: the integrated state's components
// (x1, v1, w_motor, w_load, w_friction, w_p1).

// NY: generated into the prelude from src/integrator/components.rs.

// The mesh powers (p1, p2) from a derivative's components 4 and 5
// (w_friction's rate p1 + p2, and the integral of p1's rate p1): the one
// place in the shader that says which components they are.
fn powers(k4: real, k5: real) -> vec2<real> {
    return vec2<real>(k5, k4 - k5);
}
