//! Lane parameters: the names of docs/model.md section 9, partial specifications
//! (what a sweep file, an axis or a lane-table row sets) and their resolution
//! into a validated, complete [`Params`].
//!
//! Every fact about a parameter (its name, unit, default, which law owns
//! it, the values it may take) is stated once, in the table of
//! [`table`]; the `Num` enum, the defaults, ownership, validation, the
//! guide's table (docs/guide.md) and the resolved provenance are all derived from it.

mod check;
pub mod gear;
mod lane;
pub mod paper;
mod resolve;
pub mod table;
pub mod table_name;
mod validated;
mod vary;

pub use resolve::{ParamError, Spec};
pub use table::{Bound, Def, Fallback, FrictionKind, MotorKind, Num, Owner, Param, N_NUM};
pub use table_name::{FrictionTables, TableName};
pub use validated::{LaneParams, ParamColumns, Params, Row};
pub use vary::Varying;
