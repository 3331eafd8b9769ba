//! Names for the target predicates that the core's fixed-point arithmetic
//! chooses its code by, so that `src/` reads `#[cfg(armv6m)]` where it would
//! spell out `all(target_arch = "arm", not(target_has_atomic = "32"))`:
//!
//! - `armv6m`: Armv6-M (Cortex-M0, M0+, M1), recognised as the Arm cores
//!   without 32-bit compare-and-swap. Its `muls` gives the low 32 bits of a
//!   product only, so a 64-bit product is a library call.
//! - `armv6m_inline_mul`: `armv6m` without the `compact-mul` feature: the
//!   Q8.24 product from 16-bit limbs, written out at every call.
//! - `wide_mul`: 64-bit targets and WebAssembly, whose native 64-bit
//!   product is one or two instructions.
//! - `div_by_reciprocal`: the 32-bit cores without a divide instruction
//!   (`armv6m`, RISC-V without `M`), where a two-word division goes
//!   through a 16-bit reciprocal rather than the library's 64-bit one.
//! - `hard_float`: targets whose `f32` arithmetic and conversions are
//!   instructions: x86, AArch64, WebAssembly, Arm's `eabihf` targets and
//!   RISC-V with `F` or `D` (read from the triple's ISA string, such as
//!   `riscv32imafc`, as stable Rust does not report RISC-V's `f` feature
//!   to `cfg`). Elsewhere `f32` is a library call per operation.
//! - `rv32_soft_float`: 32-bit RISC-V without `hard_float` (RV32IMAC),
//!   where the shadow query of a single ray is one out-of-line call and a
//!   candidate mask's lowest bit comes from a table.
//!
//! Nothing else is decided here; the same source builds with or without
//! these names on every target (they only choose between equal results).

use std::env;

fn main() {
    println!("cargo::rerun-if-changed=build.rs");
    for name in ["armv6m", "armv6m_inline_mul", "wide_mul", "div_by_reciprocal", "hard_float", "rv32_soft_float"] {
        println!("cargo::rustc-check-cfg=cfg({name})");
    }
    let arch = env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default();
    let atomics = env::var("CARGO_CFG_TARGET_HAS_ATOMIC").unwrap_or_default();
    let width = env::var("CARGO_CFG_TARGET_POINTER_WIDTH").unwrap_or_default();
    let features = env::var("CARGO_CFG_TARGET_FEATURE").unwrap_or_default();
    let compact_mul = env::var_os("CARGO_FEATURE_COMPACT_MUL").is_some();
    let armv6m = arch == "arm" && !atomics.split(',').any(|a| a == "32");
    if armv6m {
        println!("cargo::rustc-cfg=armv6m");
        if !compact_mul {
            println!("cargo::rustc-cfg=armv6m_inline_mul");
        }
    }
    let wide_mul = width == "64" || arch == "wasm32";
    if wide_mul {
        println!("cargo::rustc-cfg=wide_mul");
    }
    let riscv_without_divide = arch == "riscv32" && !features.split(',').any(|f| f == "m");
    if !wide_mul && (armv6m || riscv_without_divide) {
        println!("cargo::rustc-cfg=div_by_reciprocal");
    }
    let abi = env::var("CARGO_CFG_TARGET_ABI").unwrap_or_default();
    let triple = env::var("TARGET").unwrap_or_default();
    let riscv_float = arch.starts_with("riscv")
        && (features.split(',').any(|f| f == "f" || f == "d")
            || triple
                .split('-')
                .next()
                .and_then(|isa| isa.strip_prefix("riscv32").or_else(|| isa.strip_prefix("riscv64")))
                .is_some_and(|letters| letters.contains(['f', 'd', 'g'])));
    let hard_float = matches!(arch.as_str(), "x86" | "x86_64" | "aarch64" | "wasm32")
        || (arch == "arm" && abi == "eabihf")
        || riscv_float;
    if hard_float {
        println!("cargo::rustc-cfg=hard_float");
    }
    if arch == "riscv32" && !hard_float {
        println!("cargo::rustc-cfg=rv32_soft_float");
    }
}
