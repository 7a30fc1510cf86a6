//! The traced lanes of `traces.csv`, the first few of them, decimated as
//! they are read.

use std::path::Path;

use super::scan::{bad_row, column, num, open_csv, Folder, TRACES_SHOWN};
use super::trace::TraceData;
use crate::columns::LANE;
use crate::error::{Error, Result};
use crate::output::names::TRACES;

impl Folder {
    /// The first traced lanes of `traces.csv`, decimated: `traced` gives
    /// each lane the sweep traces with its horizon.
    pub(super) fn read_traces(&mut self, dir: &Path, traced: &[(u64, f64)]) -> Result<()> {
        let path = dir.join(TRACES);
        if !path.exists() {
            return Ok(());
        }
        let mut rd = open_csv(&path)?;
        let head = rd.byte_headers().map_err(|e| bad_row(&path, e))?.clone();
        let c = |n: &str| column(&path, &head, n);
        let (lane_c, t_c, v_c, s1_c, s2_c, psi_c) =
            (c(LANE)?, c("t")?, c("v1")?, c("s1")?, c("s2")?, c("psi")?);
        let mut rec = csv::ByteRecord::new();
        let mut last_t = f64::NAN;
        while rd
            .read_byte_record(&mut rec)
            .map_err(|e| bad_row(&path, e))?
        {
            let at = || rec.position().map(|p| format!("line {}", p.line()));
            let lane = num(&path, &rec, lane_c, LANE)?;
            let horizon = traced
                .iter()
                .find(|(l, _)| *l as f64 == lane)
                .map(|x| x.1)
                .ok_or_else(|| {
                    Error::input(
                        &path,
                        at(),
                        Some(LANE),
                        format!("lane {lane} is not a traced lane of the run; not its traces.csv"),
                    )
                })?;
            let lane = lane as u64;
            if self.traces.last().is_none_or(|t| t.lane != lane) {
                if self.traces.iter().any(|t| t.lane == lane) {
                    return Err(Error::input(
                        &path,
                        at(),
                        Some(LANE),
                        format!("the rows of lane {lane} are not together; not a tswm traces.csv"),
                    ));
                }
                if self.traces.len() == TRACES_SHOWN {
                    break;
                }
                self.traces.push(TraceData::new(lane, horizon));
                last_t = f64::NAN;
            }
            let t = num(&path, &rec, t_c, "t")?;
            let vals = [
                num(&path, &rec, v_c, "v1")?,
                num(&path, &rec, s1_c, "s1")?,
                num(&path, &rec, s2_c, "s2")?,
                num(&path, &rec, psi_c, "psi")?,
            ];
            // Two rows with one t are an event's before and after.
            let event = t == last_t;
            last_t = t;
            self.traces.last_mut().expect("pushed").add(t, vals, event);
        }
        Ok(())
    }
}
