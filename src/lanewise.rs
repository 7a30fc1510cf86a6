//! Values of one lane and their columns over W lanes, from one definition.
//!
//! The CPU path steps W lanes in lockstep as vector code: what it keeps of
//! them (constants, trial steps, states, error budgets) is a struct of
//! arrays, `x[j]` lane j's value of field x, while the one-lane code (the
//! lane automaton, traces, `tswm check`) reads a plain struct. Both are
//! declared once, by [`lanewise_struct!`](crate::lanewise_struct): the struct, its columns over W
//! lanes, and the moves of one lane in and out of them. The W = 1 case of
//! the columns is the one-lane path's own.

/// A per-lane value whose columns over W lanes are [`Lanewise::Cols`].
pub trait Lanewise: Copy {
    /// The value of W lanes: `[Self; W]` for a number or a flag, a struct
    /// of such arrays for a struct ([`lanewise_struct!`](crate::lanewise_struct)).
    type Cols<const W: usize>: Copy;

    /// Every lane at this type's zero.
    fn zero<const W: usize>() -> Self::Cols<W>;

    /// Lane j's value.
    fn get<const W: usize>(cols: &Self::Cols<W>, j: usize) -> Self;

    /// Sets lane j's value.
    fn set<const W: usize>(cols: &mut Self::Cols<W>, j: usize, v: Self);

    /// The columns of one lane (the W = 1 case).
    #[inline(always)]
    fn one(self) -> Self::Cols<1> {
        let mut c = Self::zero::<1>();
        Self::set(&mut c, 0, self);
        c
    }
}

/// [`Lanewise`] for values stored as they are, one array element a lane:
/// `lanewise_scalar!(f64 = 0.0, MyEnum = MyEnum::A)` (the value is the
/// type's zero).
#[macro_export]
macro_rules! lanewise_scalar {
    ($($t:ty = $zero:expr),* $(,)?) => {$(
        impl $crate::lanewise::Lanewise for $t {
            type Cols<const W: usize> = [$t; W];
            #[inline(always)]
            fn zero<const W: usize>() -> [$t; W] {
                [$zero; W]
            }
            #[inline(always)]
            fn get<const W: usize>(cols: &[$t; W], j: usize) -> $t {
                cols[j]
            }
            #[inline(always)]
            fn set<const W: usize>(cols: &mut [$t; W], j: usize, v: $t) {
                cols[j] = v;
            }
        }
    )*};
}

crate::lanewise_scalar!(f64 = 0.0, bool = false, u32 = 0, i32 = 0);

/// An array of K values a lane is K columns: `[[T; W]; K]` for numbers.
impl<T: Lanewise, const K: usize> Lanewise for [T; K] {
    type Cols<const W: usize> = [T::Cols<W>; K];
    #[inline(always)]
    fn zero<const W: usize>() -> Self::Cols<W> {
        [T::zero::<W>(); K]
    }
    #[inline(always)]
    fn get<const W: usize>(cols: &Self::Cols<W>, j: usize) -> Self {
        std::array::from_fn(|i| T::get(&cols[i], j))
    }
    #[inline(always)]
    fn set<const W: usize>(cols: &mut Self::Cols<W>, j: usize, v: Self) {
        for (c, v) in cols.iter_mut().zip(v) {
            T::set(c, j, v);
        }
    }
}

/// Declares a per-lane struct and its columns over W lanes:
///
/// ```ignore
/// lanewise_struct! {
///     /// One lane's trial step.
///     #[derive(Clone, Copy, Debug)]
///     pub struct Trial, Trials {
///         /// The state at the step's end.
///         pub y1: [f64; NY],
///         pub err: f64,
///     }
/// }
/// ```
///
/// gives `Trial` as written, `Trials<const W: usize>` with each field's
/// columns (`y1: [[f64; W]; NY]`, `err: [f64; W]`), and `Trial:
/// Lanewise` (zero, get and set lane j, field by field). Every field's
/// type must be [`Lanewise`].
#[macro_export]
macro_rules! lanewise_struct {
    (
        $(#[$meta:meta])*
        $vis:vis struct $one:ident, $many:ident {
            $( $(#[$fmeta:meta])* $fvis:vis $field:ident : $ty:ty ),* $(,)?
        }
    ) => {
        $(#[$meta])*
        $vis struct $one {
            $( $(#[$fmeta])* $fvis $field: $ty, )*
        }

        #[doc = concat!("[`", stringify!($one), "`] of W lanes, one column a field (`x[j]`, or `x[i][j]` for an array, is lane j's).")]
        #[derive(Clone, Copy)]
        $vis struct $many<const W: usize> {
            $( $(#[$fmeta])* $fvis $field: <$ty as $crate::lanewise::Lanewise>::Cols<W>, )*
        }

        impl $crate::lanewise::Lanewise for $one {
            type Cols<const W: usize> = $many<W>;
            #[inline(always)]
            fn zero<const W: usize>() -> $many<W> {
                $many { $( $field: <$ty as $crate::lanewise::Lanewise>::zero::<W>(), )* }
            }
            #[inline(always)]
            fn get<const W: usize>(cols: &$many<W>, j: usize) -> $one {
                $one { $( $field: <$ty as $crate::lanewise::Lanewise>::get(&cols.$field, j), )* }
            }
            #[inline(always)]
            fn set<const W: usize>(cols: &mut $many<W>, j: usize, v: $one) {
                $( <$ty as $crate::lanewise::Lanewise>::set(&mut cols.$field, j, v.$field); )*
            }
        }

        impl<const W: usize> $many<W> {
            /// Every lane at zero.
            #[inline(always)]
            #[allow(dead_code)]
            pub fn zero() -> Self {
                <$one as $crate::lanewise::Lanewise>::zero::<W>()
            }

            /// Lane j's values.
            #[inline(always)]
            #[allow(dead_code)]
            pub fn lane(&self, j: usize) -> $one {
                <$one as $crate::lanewise::Lanewise>::get(self, j)
            }

            /// Sets lane j's values.
            #[inline(always)]
            #[allow(dead_code)]
            pub(crate) fn set_lane(&mut self, j: usize, v: $one) {
                <$one as $crate::lanewise::Lanewise>::set(self, j, v)
            }
        }
    };
}

/// The array of f(0), .., f(W − 1), by a plain loop that is always
/// inlined: `std::array::from_fn` may be left out of line, and then runs
/// without the caller's vector instructions.
#[inline(always)]
pub(crate) fn by_lane<T: Copy + Default, const W: usize>(f: impl Fn(usize) -> T) -> [T; W] {
    let mut a = [T::default(); W];
    for (j, v) in a.iter_mut().enumerate() {
        *v = f(j);
    }
    a
}

#[cfg(test)]
mod tests {
    use super::*;

    lanewise_struct! {
        /// A test struct.
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub struct Pair, Pairs {
            /// A number.
            pub a: f64,
            /// Three flags.
            pub b: [bool; 3],
        }
    }

    #[test]
    fn a_lane_goes_into_its_columns_and_back() {
        let mut c = Pairs::<4>::zero();
        let p = Pair {
            a: 2.5,
            b: [true, false, true],
        };
        c.set_lane(2, p);
        assert_eq!(c.lane(2), p);
        assert_eq!(c.a, [0.0, 0.0, 2.5, 0.0]);
        assert_eq!(c.b[2], [false, false, true, false]);
        assert_eq!(Pairs::<1>::lane(&p.one(), 0), p);
    }
}
