// Mirrors src/integrator/rhs.rs: the right-hand side of the state's
// equations in one mode.

struct Deriv { k: array<real, NY>, d: real }

fn rhs(l: Lane, m: Mode, v: real) -> Deriv {
    let mo = motion(l, m, v);
    let v2 = v * l.tan_g;
    let p1 = mo.s1 * v;
    let p2 = mo.s2 * v2;
    return Deriv(array<real, NY>(v, mo.acc, mo.f1 * v, l.f2 * v2, p1 + p2, p1), mo.d);
}
