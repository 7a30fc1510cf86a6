//! A sweep as `sweep.resolved.toml` writes it: every lane's source spelled
//! out, so that the file alone gives the same lanes again.

use super::{AxisValues, Sweep};
use crate::params::{FrictionKind, MotorKind, Num, Param};

impl Sweep {
    /// The sweep as TOML with every lane's source spelled out: base with
    /// defaults resolved, axes as value lists, the study and the table.
    pub(crate) fn resolved_toml(&self) -> toml::Table {
        let mut t = toml::Table::new();
        t.insert("base".into(), self.base_toml().into());
        let grid: Vec<toml::Value> = self.axes.iter().map(axis_toml).collect();
        if !grid.is_empty() {
            t.insert("grid".into(), grid.into());
        }
        if let Some(st) = &self.study {
            let (sampling, tols) = study_toml(st);
            let name = if st.sensitivity.is_some() {
                "sensitivity"
            } else {
                "sampling"
            };
            t.insert(name.into(), sampling.into());
            t.insert("tolerance".into(), tols.into());
        }
        if let Some(tr) = &self.trace {
            let mut x = toml::Table::new();
            let lanes: Vec<toml::Value> = tr.lanes.iter().map(|&l| (l as i64).into()).collect();
            x.insert("lanes".into(), lanes.into());
            x.insert("dt".into(), tr.dt.into());
            t.insert("trace".into(), x.into());
        }
        if let Some(s) = &self.search {
            let mut x = toml::Table::new();
            x.insert("param".into(), s.param.name().into());
            x.insert("from".into(), s.from.into());
            x.insert("to".into(), s.to.into());
            x.insert("require".into(), s.require.text().into());
            x.insert("tol".into(), s.tol.into());
            if let Some(a) = s.at_least {
                x.insert("at_least".into(), a.into());
            }
            if s.quantiles {
                x.insert("quantiles".into(), true.into());
            }
            t.insert("search".into(), x.into());
        }
        if self.report != super::ReportSpec::default() {
            t.insert("report".into(), report_toml(&self.report).into());
        }
        if !self.tables.is_empty() {
            let one = |tb: &crate::model::FrictionTable| {
                let mut x = toml::Table::new();
                x.insert("vs".into(), floats(&tb.vs[..tb.n]));
                x.insert("mu".into(), floats(&tb.mu[..tb.n]));
                x
            };
            let x = if self.tables.unnamed() {
                one(&self.tables.tables[0])
            } else {
                let mut x = toml::Table::new();
                for (name, tb) in self.tables.names.iter().zip(&self.tables.tables) {
                    x.insert(name.to_string(), one(tb).into());
                }
                x
            };
            t.insert("friction_table".into(), x.into());
        }
        t
    }

    /// Whether any lane may be given in gear terms: the base, an axis or a
    /// tolerance sets a gear term.
    fn uses_gear_terms(&self) -> bool {
        let gear = |p: Param| matches!(p, Param::Num(n) if crate::params::gear::GEAR.contains(&n));
        crate::params::gear::GEAR
            .iter()
            .any(|&g| self.base.num[g as usize].is_some())
            || self.axes.iter().any(|a| gear(a.param))
            || self
                .study
                .as_ref()
                .is_some_and(|s| s.params.iter().any(|t| gear(Param::Num(t.param))))
    }

    /// The laws a lane may have: the base's, or the words of an axis over
    /// laws.
    fn laws(&self) -> Vec<(MotorKind, FrictionKind)> {
        let words = |p: Param| {
            self.axes
                .iter()
                .find_map(|a| match (&a.values, a.param == p) {
                    (AxisValues::Words(w), true) => Some(w.clone()),
                    _ => None,
                })
        };
        let motors: Vec<MotorKind> = match words(Param::Motor) {
            Some(w) => super::laws::motors_on(&w).collect(),
            None => vec![self.base.motor.unwrap_or(MotorKind::Kloss)],
        };
        let frictions: Vec<FrictionKind> = match words(Param::Friction) {
            Some(w) => super::laws::frictions_on(&w).collect(),
            None => vec![self.base.friction.unwrap_or(FrictionKind::Paper)],
        };
        motors
            .iter()
            .flat_map(|&m| frictions.iter().map(move |&f| (m, f)))
            .collect()
    }

    /// The base as set, plus the defaults of the laws its lanes may have
    /// (each lane takes those its own law uses: `Sweep::lane_spec`); not
    /// validated, since axes and samples may supply what it lacks.
    fn base_toml(&self) -> toml::Table {
        let mut base = toml::Table::new();
        let motor = self.base.motor.unwrap_or(MotorKind::Kloss);
        let friction = self.base.friction.unwrap_or(FrictionKind::Paper);
        let laws = self.laws();
        base.insert("motor".into(), motor.name().into());
        base.insert("friction".into(), friction.name().into());
        if let Some(t) = self.base.friction_table {
            base.insert("friction_table".into(), t.to_string().into());
        }
        // Where gear terms are used, a wedge default is not written: beside
        // its gear form it would give one quantity twice.
        let gear_terms = self.uses_gear_terms();
        for n in Num::ALL {
            let law_default = laws.iter().any(|&(m, f)| n.def().owner.applies(m, f))
                && !(gear_terms && crate::params::gear::has_gear_form(n));
            let v =
                self.base.num[n as usize].or(if law_default { n.default_value() } else { None });
            if let Some(v) = v {
                base.insert(n.name().into(), v.into());
            }
        }
        base
    }
}

/// A grid axis: its values as a list, or its range.
fn axis_toml(a: &super::Axis) -> toml::Value {
    let mut x = toml::Table::new();
    x.insert("param".into(), a.param.name().into());
    match &a.values {
        &AxisValues::Range { from, to, n, log } => {
            x.insert("from".into(), from.into());
            x.insert("to".into(), to.into());
            x.insert("n".into(), (n as i64).into());
            x.insert("scale".into(), if log { "log" } else { "linear" }.into());
        }
        AxisValues::List(v) => {
            x.insert("values".into(), floats(v));
        }
        AxisValues::Words(w) => {
            let v: Vec<toml::Value> = w.iter().map(|s| s.clone().into()).collect();
            x.insert("values".into(), v.into());
        }
    }
    x.into()
}

/// A study's `[sampling]` and its `[[tolerance]]` entries.
fn study_toml(st: &super::Study) -> (toml::Table, Vec<toml::Value>) {
    let mut s = toml::Table::new();
    match &st.sensitivity {
        Some(sn) => {
            s.insert("method".into(), "sobol".into());
            s.insert("n".into(), (sn.base as i64).into());
            s.insert("seed".into(), toml::Value::Integer(st.seed as i64));
            s.insert("bootstrap".into(), (sn.bootstrap as i64).into());
            s.insert("confidence".into(), sn.confidence.into());
            if !sn.results.is_empty() {
                let v: Vec<toml::Value> = sn.results.iter().map(|r| r.clone().into()).collect();
                s.insert("results".into(), v.into());
            }
        }
        None => {
            s.insert("method".into(), serde_name(&st.method));
            s.insert("n".into(), (st.n as i64).into());
            s.insert("seed".into(), toml::Value::Integer(st.seed as i64));
        }
    }
    let tols = st
        .params
        .iter()
        .map(|p| {
            let mut x = toml::Table::new();
            x.insert("param".into(), p.param.name().into());
            x.insert("dist".into(), serde_name(&p.dist));
            x.insert(
                if p.relative { "tol_rel" } else { "tol" }.into(),
                p.tol.into(),
            );
            x.into()
        })
        .collect();
    (s, tols)
}

/// The `[report]` table, keys that were set only.
fn report_toml(r: &super::ReportSpec) -> toml::Table {
    let mut x = toml::Table::new();
    if let Some(t) = &r.title {
        x.insert("title".into(), t.clone().into());
    }
    if !r.axes.is_empty() {
        let a: Vec<toml::Value> = r.axes.iter().map(|a| a.name().into()).collect();
        x.insert("axes".into(), a.into());
    }
    if !r.results.is_empty() {
        let v: Vec<toml::Value> = r.results.iter().map(|s| s.clone().into()).collect();
        x.insert("results".into(), v.into());
    }
    if r.panels > 0 {
        x.insert("panels".into(), (r.panels as i64).into());
    }
    if let Some(q) = &r.require {
        x.insert("require".into(), q.text().into());
        x.insert("at_least".into(), q.at_least.into());
    }
    if !r.pareto.is_empty() {
        let v: Vec<toml::Value> = r.pareto.iter().map(|o| o.text().into()).collect();
        x.insert("pareto".into(), v.into());
    }
    x
}

/// A list of floats as a TOML array.
fn floats(v: &[f64]) -> toml::Value {
    toml::Value::Array(v.iter().map(|&x| x.into()).collect())
}

/// An enum's spelling in files, as its serde derive writes it (one source
/// of truth for the names).
fn serde_name<T: serde::Serialize>(v: &T) -> toml::Value {
    toml::Value::try_from(v).expect("unit enum variants serialize as strings")
}
