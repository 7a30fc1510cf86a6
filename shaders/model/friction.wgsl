// Mirrors src/model/friction.rs: the friction laws' μ(Vs).

// The agma law: its constants (AGMA_*, FT_PER_MIN_PER_M_PER_S) are
// generated into the prelude from src/model/laws.rs.

fn tan_small(x: real) -> real {
    if (abs(x) > 0.15) { return tan_r(x); }
    let x2 = x * x;
    var p: real = 62.0 / 2835.0;
    p = p * x2 + 17.0 / 315.0;
    p = p * x2 + 2.0 / 15.0;
    p = p * x2 + 1.0 / 3.0;
    return x + x * x2 * p;
}

// Point i of table t (see `GpuGlobals`).
fn table_at(t: u32, i: u32) -> vec2<real> {
    let k = t * TABLE_VEC4S + i / 4u;
    return vec2<real>(g.table_vs[k][i % 4u], g.table_mu[k][i % 4u]);
}

fn agma_mu(vs: real, upper: bool) -> real {
    let v = max(vs, 0.0) * FT_PER_MIN_PER_M_PER_S;
    // pow(0, e) is not defined in WGSL: Vs^e = 0 at rest.
    let e = select(AGMA_LOW_E, AGMA_HIGH_E, upper);
    var pw: real = 0.0;
    if (v > 0.0) { pw = pow_r(v, e); }
    if (upper) { return AGMA_HIGH_A * exp_r(-AGMA_HIGH_B * pw) + AGMA_HIGH_C; }
    return AGMA_LOW_A * exp_r(-AGMA_LOW_B * pw);
}

// The stribeck law from its slots (μc, μs, v_st, δ, kv).
fn stribeck_mu(s: array<real, LAW_SLOTS>, vs: real) -> real {
    // pow(0, δ) is not defined in WGSL: (Vs/v_st)^δ = 0 at rest.
    var pw: real = 0.0;
    if (vs > 0.0) { pw = pow_r(vs / s[2], s[3]); }
    return s[0] + (s[1] - s[0]) * exp_r(-pw) + s[4] * vs;
}

// The lane's law on its slots `l.law` (the law's parameters in the
// parameter table's order), as tan ρ: a coefficient μ over cos αn.
// `vs` may be below 0, past a rest a step overshoots: a table reads its
// line there, the other laws their speed at 0 (see src/model/friction.rs).
fn mu_sliding(l: Lane, vs: real, branch: u32) -> real {
    let s = l.law;
    let clamped = max(vs, 0.0);
    if (l.friction == FRICTION_PAPER) {
        return tan_small(paper_rho(s[0], s[1], s[2], clamped));
    }
    if (l.friction == FRICTION_COULOMB) { return s[0] * l.inv_cos_an; }
    if (l.friction == FRICTION_AGMA) { return agma_mu(clamped, branch == 1u) * l.inv_cos_an; }
    if (l.friction == FRICTION_STRIBECK) { return stribeck_mu(s, clamped) * l.inv_cos_an; }
    if (l.friction != FRICTION_TABLE || l.table >= g.n_tables) {
        // No such law or table: NaN makes the lane `nonfinite`, never a number.
        return real(bitcast<f32>(0x7fc00000u));
    }
    return table_mu_on(l.table, branch, vs) * l.inv_cos_an;
}

// Points in table t.
fn table_n(t: u32) -> u32 {
    return g.table_n[t / 4u][t % 4u];
}

// `FrictionTable::mu_on`: μ on piece k of table t (flat past the ends,
// else the line through points k − 1 and k, extended past them).
fn table_mu_on(t: u32, k: u32, vs: real) -> real {
    let n = table_n(t);
    if (k == 0u) { return table_at(t, 0u).y; }
    if (k >= n) { return table_at(t, n - 1u).y; }
    let prev = table_at(t, k - 1u);
    let cur = table_at(t, k);
    let w = (vs - prev.x) / (cur.x - prev.x);
    return prev.y + w * (cur.y - prev.y);
}

// Whether the lane's law is a table that exists.
fn has_table(l: Lane) -> bool {
    return l.friction == FRICTION_TABLE && l.table < g.n_tables;
}

// `branch_of` in src/model/friction.rs: the branch of the lane's law that
// sliding speed `vs` is on (a table's piece: its speeds at or below vs).
fn branch_of(l: Lane, vs: real) -> u32 {
    if (has_table(l)) {
        var k = 0u;
        for (var i = 0u; i < table_n(l.table); i++) {
            if (table_at(l.table, i).x <= vs) { k += 1u; }
        }
        return k;
    }
    return select(0u, 1u, above_branch(l, vs));
}

// `branch_edges` in src/model/friction.rs: x, y: the sliding speeds
// bounding branch b (∓3e38, "never", past the ends).
fn branch_edges(l: Lane, b: u32) -> vec2<real> {
    var e = vec2<real>(-3.0e38, 3.0e38);
    if (has_table(l)) {
        let n = table_n(l.table);
        if (b > 0u) { e.x = table_at(l.table, min(b, n) - 1u).x; }
        if (b < n) { e.y = table_at(l.table, b).x; }
    } else if (l.branch_speed < 1.0e38) {
        if (b == 0u) { e.y = l.branch_speed; } else { e.x = l.branch_speed; }
    }
    return e;
}
