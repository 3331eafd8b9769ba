//! Puts this board's `memory.x` on the linker search path (cortex-m-rt's
//! `link.x` includes it), and beside it the common crate's `ram_code.x`,
//! which `memory.x` includes.
use std::{env, fs, path::PathBuf};

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("OUT_DIR"));
    fs::write(out.join("memory.x"), include_bytes!("memory.x")).expect("write memory.x");
    fs::write(out.join("ram_code.x"), include_bytes!("../common/ram_code.x")).expect("write ram_code.x");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=../common/ram_code.x");
    println!("cargo:rerun-if-changed=build.rs");
}
