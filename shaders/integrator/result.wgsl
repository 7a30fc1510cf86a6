// Mirrors src/integrator/result.rs: how a lane ended.

// Status codes (S_*): generated into the prelude from `Status` in
// src/integrator/result.rs.
