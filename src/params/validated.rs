//! Validated parameters: one lane's ([`Params`]), and a chunk of lanes'
//! as columns ([`ParamColumns`]): one f64 column per numeric parameter
//! (NaN where a lane's laws do not use it), and a column for each lane's
//! laws, friction table and gear radii. The lane source generates a
//! chunk straight into the columns; the backends read a lane's
//! parameters from them, and the results table takes its parameter
//! columns from them as they are.

use super::table::{FrictionKind, MotorKind, Num, N_NUM};
use super::table_name::TableName;

/// A complete, validated parameter set. Numeric values that the chosen laws
/// do not use are NaN (written as empty cells).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// Numeric values, indexed by [`Num`].
    pub num: [f64; N_NUM],
    /// Motor law.
    pub motor: MotorKind,
    /// Friction law.
    pub friction: FrictionKind,
    /// The friction table a `friction = table` lane names, as given.
    pub friction_table: Option<TableName>,
    /// Index of the lane's friction table among the run's (0 unless
    /// `friction = table`).
    pub table: usize,
    /// Pitch radii R1, R2 of a lane given in gear terms, m; NaN without
    /// a geometry.
    pub r1: f64,
    /// See [`Params::r1`].
    pub r2: f64,
}

impl Params {
    /// A numeric value (NaN when not applicable).
    #[inline]
    pub fn get(&self, p: Num) -> f64 {
        self.num[p as usize]
    }
}

/// What a lane's model constants are derived from: one validated lane's
/// parameters, a row of a [`ParamColumns`] or a [`Params`].
pub trait LaneParams {
    /// A numeric value (NaN when not applicable).
    fn get(&self, p: Num) -> f64;
    /// Motor law.
    fn motor(&self) -> MotorKind;
    /// Friction law.
    fn friction(&self) -> FrictionKind;
    /// Index of the lane's friction table among the run's.
    fn table(&self) -> usize;
    /// Pitch radii R1, R2 of a lane given in gear terms, m; NaN without.
    fn radii(&self) -> (f64, f64);
}

impl LaneParams for Params {
    #[inline]
    fn get(&self, p: Num) -> f64 {
        self.num[p as usize]
    }
    fn motor(&self) -> MotorKind {
        self.motor
    }
    fn friction(&self) -> FrictionKind {
        self.friction
    }
    fn table(&self) -> usize {
        self.table
    }
    fn radii(&self) -> (f64, f64) {
        (self.r1, self.r2)
    }
}

/// The parameters of a chunk of lanes, one column each (a struct of
/// arrays): the layout the results table's parameter columns take, so a
/// chunk's lanes are copied column by column, never lane by lane.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ParamColumns {
    num: Vec<Vec<f64>>,
    motor: Vec<MotorKind>,
    friction: Vec<FrictionKind>,
    friction_table: Vec<Option<TableName>>,
    table: Vec<usize>,
    r1: Vec<f64>,
    r2: Vec<f64>,
}

/// Lane `i` of a [`ParamColumns`].
#[derive(Clone, Copy)]
pub struct Row<'a> {
    cols: &'a ParamColumns,
    i: usize,
}

impl LaneParams for Row<'_> {
    #[inline]
    fn get(&self, p: Num) -> f64 {
        self.cols.num[p as usize][self.i]
    }
    fn motor(&self) -> MotorKind {
        self.cols.motor[self.i]
    }
    fn friction(&self) -> FrictionKind {
        self.cols.friction[self.i]
    }
    fn table(&self) -> usize {
        self.cols.table[self.i]
    }
    fn radii(&self) -> (f64, f64) {
        (self.cols.r1[self.i], self.cols.r2[self.i])
    }
}

impl ParamColumns {
    /// Empty columns with room for `n` lanes.
    pub fn with_capacity(n: usize) -> ParamColumns {
        ParamColumns {
            num: (0..N_NUM).map(|_| Vec::with_capacity(n)).collect(),
            motor: Vec::with_capacity(n),
            friction: Vec::with_capacity(n),
            friction_table: Vec::with_capacity(n),
            table: Vec::with_capacity(n),
            r1: Vec::with_capacity(n),
            r2: Vec::with_capacity(n),
        }
    }

    /// Lanes held.
    pub fn len(&self) -> usize {
        self.motor.len()
    }

    /// Whether no lane is held.
    pub fn is_empty(&self) -> bool {
        self.motor.is_empty()
    }

    /// Removes every lane (the room stays).
    pub(crate) fn clear(&mut self) {
        if self.num.len() != N_NUM {
            self.num = vec![Vec::new(); N_NUM];
        }
        self.num.iter_mut().for_each(Vec::clear);
        self.motor.clear();
        self.friction.clear();
        self.friction_table.clear();
        self.table.clear();
        self.r1.clear();
        self.r2.clear();
    }

    /// Appends a lane.
    pub fn push(&mut self, p: &Params) {
        self.push_checked(&p.num, p.motor, p.friction, p.friction_table, p.table);
        if let (Some(r1), Some(r2)) = (self.r1.last_mut(), self.r2.last_mut()) {
            (*r1, *r2) = (p.r1, p.r2);
        }
    }

    /// Appends a lane in wedge terms from its checked values (no gear
    /// radii).
    pub(super) fn push_checked(
        &mut self,
        num: &[f64; N_NUM],
        motor: MotorKind,
        friction: FrictionKind,
        friction_table: Option<TableName>,
        table: usize,
    ) {
        if self.num.len() != N_NUM {
            self.num = vec![Vec::new(); N_NUM];
        }
        for (c, &v) in self.num.iter_mut().zip(num) {
            c.push(v);
        }
        self.motor.push(motor);
        self.friction.push(friction);
        self.friction_table.push(friction_table);
        self.table.push(table);
        self.r1.push(f64::NAN);
        self.r2.push(f64::NAN);
    }

    /// Appends lanes `rows` of `src`, column by column.
    pub(crate) fn extend_from(&mut self, src: &ParamColumns, rows: std::ops::Range<usize>) {
        if self.num.len() != N_NUM {
            self.num = vec![Vec::new(); N_NUM];
        }
        for (c, s) in self.num.iter_mut().zip(&src.num) {
            c.extend_from_slice(&s[rows.clone()]);
        }
        self.motor.extend_from_slice(&src.motor[rows.clone()]);
        self.friction.extend_from_slice(&src.friction[rows.clone()]);
        self.friction_table
            .extend_from_slice(&src.friction_table[rows.clone()]);
        self.table.extend_from_slice(&src.table[rows.clone()]);
        self.r1.extend_from_slice(&src.r1[rows.clone()]);
        self.r2.extend_from_slice(&src.r2[rows]);
    }

    /// The bytes a lane takes in these columns.
    pub(crate) const LANE_BYTES: usize = N_NUM * 8
        + std::mem::size_of::<MotorKind>()
        + std::mem::size_of::<FrictionKind>()
        + std::mem::size_of::<Option<TableName>>()
        + std::mem::size_of::<usize>()
        + 16;

    /// Takes the column of `p` out, leaving it empty until
    /// [`ParamColumns::put_num`] puts it back (a batch of the results
    /// table holds it meanwhile): no lane may be read in between.
    pub(crate) fn take_num(&mut self, p: Num) -> Vec<f64> {
        std::mem::take(&mut self.num[p as usize])
    }

    /// Puts back a column [`ParamColumns::take_num`] took.
    pub(crate) fn put_num(&mut self, p: Num, values: Vec<f64>) {
        self.num[p as usize] = values;
    }

    /// Lane `i`, read in place.
    #[inline]
    pub fn row(&self, i: usize) -> Row<'_> {
        Row { cols: self, i }
    }

    /// Lane `i` as one parameter set.
    pub fn params(&self, i: usize) -> Params {
        Params {
            num: std::array::from_fn(|k| self.num[k][i]),
            motor: self.motor[i],
            friction: self.friction[i],
            friction_table: self.friction_table[i],
            table: self.table[i],
            r1: self.r1[i],
            r2: self.r2[i],
        }
    }

    /// The column of a numeric parameter.
    pub fn num(&self, p: Num) -> &[f64] {
        &self.num[p as usize]
    }

    /// Each lane's motor law.
    pub fn motors(&self) -> &[MotorKind] {
        &self.motor
    }

    /// Each lane's friction law.
    pub(crate) fn frictions(&self) -> &[FrictionKind] {
        &self.friction
    }

    /// Each lane's friction table, as named.
    pub(crate) fn friction_tables(&self) -> &[Option<TableName>] {
        &self.friction_table
    }

    /// Every lane, as parameter sets.
    pub fn rows(&self) -> Vec<Params> {
        (0..self.len()).map(|i| self.params(i)).collect()
    }

    /// The lanes `idx` (each < len), in that order.
    pub(crate) fn gather(&self, idx: impl IntoIterator<Item = usize>) -> ParamColumns {
        let mut out = ParamColumns::default();
        for i in idx {
            out.push(&self.params(i));
        }
        out
    }
}

impl FromIterator<Params> for ParamColumns {
    fn from_iter<I: IntoIterator<Item = Params>>(iter: I) -> ParamColumns {
        let mut out = ParamColumns::default();
        for p in iter {
            out.push(&p);
        }
        out
    }
}

impl<'a> FromIterator<&'a Params> for ParamColumns {
    fn from_iter<I: IntoIterator<Item = &'a Params>>(iter: I) -> ParamColumns {
        iter.into_iter().copied().collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Spec;

    /// A lane read back from the columns, in place or whole, is the lane
    /// that went in.
    #[test]
    fn a_lane_comes_back_as_it_went_in() {
        let mut a = Spec::default();
        a.set(Num::F2, -1234.5);
        let mut b = Spec {
            motor: Some(MotorKind::Constant),
            friction: Some(FrictionKind::Coulomb),
            ..Spec::default()
        };
        b.set(Num::F1, 800.0);
        b.set(Num::Mu, 0.05);
        let lanes = [a.resolve(&[]).unwrap(), b.resolve(&[]).unwrap()];
        let cols: ParamColumns = lanes.iter().collect();
        assert_eq!(cols.len(), 2);
        for (i, p) in lanes.iter().enumerate() {
            let q = cols.params(i);
            assert_eq!(format!("{p:?}"), format!("{q:?}"));
            for n in Num::ALL {
                assert_eq!(cols.row(i).get(n).to_bits(), p.get(n).to_bits());
            }
            assert_eq!(cols.row(i).motor(), p.motor);
            assert_eq!(cols.row(i).friction(), p.friction);
        }
        let back = cols.gather([1, 0]);
        assert_eq!(format!("{:?}", back.params(0)), format!("{:?}", lanes[1]));
        assert_eq!(format!("{:?}", back.params(1)), format!("{:?}", lanes[0]));
    }
}
