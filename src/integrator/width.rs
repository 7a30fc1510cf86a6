//! The CPU path's vector width: how many lanes one thread steps in
//! lockstep, and the instruction set that runs them. One binary, built
//! without `target-cpu` flags, picks the widest the core has, and steps
//! several of its vectors of f64 at once (AVX-512: 16 lanes in two
//! vectors, AVX2: 16 in four, otherwise 4 on SSE2's or NEON's f64
//! pairs): independent chains of pow and divisions keep the pipelines
//! busy where one vector would wait on each result ([`Width::natural`]
//! says what was measured).
//! `TSWM_SIMD_WIDTH` forces the number of lanes ([`LANES`], on the
//! widest instruction set still), an instruction set (`avx2`) or both
//! (`avx2:8`), for tests and comparisons. A lane's row is the same bits
//! at every width and on every instruction set (docs/numerics.md).

use std::sync::OnceLock;

/// The lane counts a width may have.
pub const LANES: [usize; 5] = [1, 2, 4, 8, 16];

/// The variable that forces a width.
pub const WIDTH_VAR: &str = "TSWM_SIMD_WIDTH";

/// An instruction set the stepper is compiled for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Isa {
    /// x86-64 with AVX-512 (F, DQ, VL).
    Avx512,
    /// x86-64 with AVX2 and FMA.
    Avx2,
    /// What the binary was built for (SSE2 on x86-64, NEON on aarch64).
    Base,
}

/// Lanes in lockstep and the instruction set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Width {
    /// Lanes one thread steps together: one of [`LANES`].
    pub lanes: usize,
    /// The instruction set.
    pub isa: Isa,
}

impl Width {
    /// "avx512 x16": for the run's provenance and `tswm devices`.
    pub fn name(&self) -> String {
        format!("{} x{}", self.isa_name(), self.lanes)
    }

    /// The instruction set's word: avx512, avx2, or what the base is
    /// (sse2 on x86-64, neon on aarch64).
    pub(crate) fn isa_name(&self) -> &'static str {
        match self.isa {
            Isa::Avx512 => "avx512",
            Isa::Avx2 => "avx2",
            Isa::Base if cfg!(target_arch = "aarch64") => "neon",
            Isa::Base if cfg!(target_arch = "x86_64") => "sse2",
            Isa::Base => "scalar",
        }
    }
}

impl Width {
    /// The width an instruction set runs at unless one is forced: 16
    /// for AVX-512 (two vectors of f64) and for AVX2 (four: measured 5 %
    /// faster than two on paper-like and heterogeneous lanes, the extra
    /// independent chains hiding the latency of pow and the divisions;
    /// three AVX-512 vectors were 9 % slower than two), 4 otherwise (two).
    pub fn natural(isa: Isa) -> Width {
        let lanes = match isa {
            Isa::Avx512 => 16,
            Isa::Avx2 => 16,
            Isa::Base => 4,
        };
        Width { lanes, isa }
    }
}

/// The instruction sets this core has, narrowest first.
pub fn isas() -> Vec<Isa> {
    let best = best_isa();
    let mut v = vec![Isa::Base];
    if best != Isa::Base {
        v.push(Isa::Avx2);
    }
    if best == Isa::Avx512 {
        v.push(Isa::Avx512);
    }
    v
}

/// The widest instruction set this core has.
pub(crate) fn best_isa() -> Isa {
    #[cfg(target_arch = "x86_64")]
    {
        // AVX-512 is used with AVX2 and FMA (the AVX-512 path enables
        // them all), so it needs them too.
        let avx2 = std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("fma");
        if avx2
            && std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512dq")
            && std::arch::is_x86_feature_detected!("avx512vl")
        {
            return Isa::Avx512;
        }
        if avx2 {
            return Isa::Avx2;
        }
    }
    Isa::Base
}

/// The width of this process: forced by [`WIDTH_VAR`], else the core's
/// widest. Err names the variable and what is allowed.
pub fn width() -> Result<Width, String> {
    static W: OnceLock<Result<Width, String>> = OnceLock::new();
    W.get_or_init(|| match std::env::var(WIDTH_VAR) {
        Err(_) => Ok(Width::natural(best_isa())),
        Ok(v) => parse(&v).map_err(|why| format!("{WIDTH_VAR}={v:?}: {why}")),
    })
    .clone()
}

/// Reads a forced width: `N` (one of [`LANES`], on the core's widest
/// instruction set), `ISA` (its natural width) or `ISA:N`, ISA one of
/// `avx512`, `avx2`, `base` that this core has.
pub fn parse(text: &str) -> Result<Width, String> {
    let allowed = || {
        let n: Vec<String> = LANES.iter().map(|n| n.to_string()).collect();
        format!(
            "allowed: {} (lanes a thread steps together), avx512, avx2 or base \
             (an instruction set), or ISA:N",
            n.join(", ")
        )
    };
    let (isa, lanes) = match text.trim().split_once(':') {
        Some((i, n)) => (Some(i.trim()), Some(n.trim())),
        None if text.trim().parse::<usize>().is_ok() => (None, Some(text.trim())),
        None => (Some(text.trim()), None),
    };
    let isa = match isa {
        None => best_isa(),
        Some("avx512") => Isa::Avx512,
        Some("avx2") => Isa::Avx2,
        Some("base") => Isa::Base,
        Some(_) => return Err(allowed()),
    };
    if !isas().contains(&isa) {
        let have: Vec<_> = isas()
            .iter()
            .map(|&i| Width::natural(i).isa_name())
            .collect();
        return Err(format!(
            "this core has no {}; it has {}",
            Width::natural(isa).isa_name(),
            have.join(", ")
        ));
    }
    let lanes = match lanes {
        None => Width::natural(isa).lanes,
        Some(n) => match n.parse::<usize>() {
            Ok(v) if LANES.contains(&v) && v.to_string() == n => v,
            _ => return Err(allowed()),
        },
    };
    Ok(Width { lanes, isa })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_forced_width_reads_as_lanes_an_instruction_set_or_both() {
        let best = best_isa();
        assert_eq!(
            parse("4").unwrap(),
            Width {
                lanes: 4,
                isa: best
            }
        );
        assert_eq!(
            parse(" base:1 ").unwrap(),
            Width {
                lanes: 1,
                isa: Isa::Base
            }
        );
        assert_eq!(parse("base").unwrap(), Width::natural(Isa::Base));
        assert_eq!(
            parse("base:16").unwrap(),
            Width {
                lanes: 16,
                isa: Isa::Base
            }
        );
        for bad in ["3", "32", "", "avx", "avx2:3", "x8", "base:", "+4", "04"] {
            assert!(parse(bad).unwrap_err().contains("allowed"), "{bad}");
        }
        if best != Isa::Avx512 {
            assert!(parse("avx512")
                .unwrap_err()
                .contains("this core has no avx512"));
        }
    }
}
