//! The instruction set the step's loops run with, chosen once at run time.
//!
//! The crate is compiled for the baseline of its target (x86-64: SSE2), so that one build runs
//! on every machine. On a CPU with AVX2 the per-tile and per-chunk work of every pass is run
//! through a second copy of the same code compiled with AVX2 enabled ([`Isa::run`]): the
//! compiler then packs more of the independent floating-point work into 256-bit registers and
//! gets more registers' worth of addressing (measured: 15 % fewer instructions per
//! particle-step for the linear scheme, docs/architecture.md).
//!
//! The two copies give bit-identical results. Both evaluate the same IEEE-754 operations in
//! the same order: Rust never contracts `a * b + c` into a fused multiply-add on its own, and
//! the code calls no `mul_add`, so enabling FMA in the instruction set changes no rounding; a
//! vector lane rounds exactly like the scalar instruction it replaces. The test
//! `crates/axmpm-core/tests/threads.rs` runs every scheme with both and compares the bits.

/// Instruction set of the hot loops.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Isa {
    /// The target's baseline (x86-64: SSE2).
    Baseline,
    /// x86-64 with AVX2 (and FMA, BMI1/2, which come with it on every AVX2 CPU).
    Avx2,
}

/// Environment variable that forces the baseline when set to `baseline`, for side-by-side
/// measurements; any other value leaves the choice to detection.
pub const ISA_VARIABLE: &str = "AXMPM_ISA";

impl Isa {
    /// The best instruction set this CPU supports, unless [`ISA_VARIABLE`] asks for the baseline.
    pub fn detect() -> Isa {
        let requested = std::env::var(ISA_VARIABLE).ok();
        if requested.as_deref() == Some("baseline") {
            return Isa::Baseline;
        }
        Isa::best_supported()
    }

    /// AVX2 when the CPU has it (with FMA and BMI2), otherwise the baseline.
    pub fn best_supported() -> Isa {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx2")
                && std::arch::is_x86_feature_detected!("fma")
                && std::arch::is_x86_feature_detected!("bmi2")
            {
                return Isa::Avx2;
            }
        }
        Isa::Baseline
    }

    /// Name for benchmark notes (`baseline`, `avx2`).
    pub fn name(self) -> &'static str {
        match self {
            Isa::Baseline => "baseline",
            Isa::Avx2 => "avx2",
        }
    }

    /// Runs `work` compiled for this instruction set. `work` is inlined into the function that
    /// carries the target features, so everything it inlines (the scheme's stencil, the
    /// formulation, the pass's loop) is compiled with them; calls it does not inline run as
    /// compiled for the baseline.
    #[inline(always)]
    pub fn run<R>(self, work: impl FnOnce() -> R) -> R {
        match self {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `Avx2` is only chosen when the CPU reports AVX2, FMA and BMI2 (`detect`).
            Isa::Avx2 => unsafe { run_avx2(work) },
            _ => work(),
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
unsafe fn run_avx2<R>(work: impl FnOnce() -> R) -> R {
    work()
}
