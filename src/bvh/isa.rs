//! Which compiled copy of the BVH leaf tests a traversal calls.
//!
//! The dispatcher (`crate::dispatch`, std only) compiles the render path
//! inside `#[target_feature]` entry points by inlining it whole. The leaf
//! tests of the tree (the primitive kernels of one leaf) are deliberately
//! *not* inlined into that path: inlined at each of their call sites into
//! each copy, they made release builds several times slower. Left out of
//! line they would be compiled once, for the baseline instruction set, and
//! BVH scenes would run their primitive kernels with SSE2 only.
//!
//! So the leaf tests are compiled once per instruction set as separate
//! functions (`leaf_avx2`, `leaf_avx512`, each a `#[target_feature]` copy of
//! the same inlined body), and the traversal calls the one named by the
//! [`LeafIsa`] token its [`BvhView`](super::BvhView) carries. The token for
//! AVX2 or AVX-512 can only be made through an `unsafe` constructor whose
//! contract is that the CPU supports it; the dispatcher makes it after
//! run-time detection. The bytes do not depend on the copy (no FMA
//! contraction is ever allowed; `tests/dispatch.rs` compares them).
#![allow(unsafe_code)]

use super::traverse::LeafVisitor;
use crate::lanes::Mask;
use crate::scalar::Scalar;

/// The instruction set of the leaf tests a traversal calls. The default
/// (`LeafIsa::default()`, the only public way to make one) is the plain
/// build: whatever the target compiles for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LeafIsa(Kind);

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
enum Kind {
    #[default]
    Plain,
    #[cfg(target_arch = "x86_64")]
    Avx2,
    #[cfg(target_arch = "x86_64")]
    Avx512,
}

impl LeafIsa {
    /// Leaf tests compiled with AVX2 (no FMA).
    ///
    /// # Safety
    /// The CPU running the traversal must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[cfg_attr(not(feature = "std"), allow(dead_code))]
    pub(crate) unsafe fn avx2() -> LeafIsa {
        LeafIsa(Kind::Avx2)
    }

    /// Leaf tests compiled with AVX-512 F, VL, BW and DQ.
    ///
    /// # Safety
    /// The CPU running the traversal must support those four features.
    #[cfg(target_arch = "x86_64")]
    #[cfg_attr(not(feature = "std"), allow(dead_code))]
    pub(crate) unsafe fn avx512() -> LeafIsa {
        LeafIsa(Kind::Avx512)
    }

    /// Short name, as `dispatch::Isa` prints it (`plain` for the default).
    pub fn name(self) -> &'static str {
        match self.0 {
            Kind::Plain => "plain",
            #[cfg(target_arch = "x86_64")]
            Kind::Avx2 => "avx2",
            #[cfg(target_arch = "x86_64")]
            Kind::Avx512 => "avx512",
        }
    }

    /// Runs `visitor`'s leaf test on `ids` for the lanes `m`, in the copy
    /// this token names.
    ///
    /// Only packets of 8 or more lanes of a scalar with
    /// [`Scalar::ISA_LEAVES`] take the per-instruction-set copies (narrower
    /// packets fit SSE2 registers): the condition is a constant of each
    /// instantiation (an inline `const`), so the other instantiations
    /// compile no extra copies (the compiler skips code behind a constant
    /// false condition when it collects what to compile).
    #[cfg_attr(not(debug_assertions), inline(always))]
    pub(super) fn leaf<S: Scalar, const W: usize, V: LeafVisitor<S, W>>(self, visitor: &mut V, ids: &[u32], m: Mask<W>) {
        if const { W < 8 || !S::ISA_LEAVES } {
            return visitor.leaf(ids, m);
        }
        match self.0 {
            Kind::Plain => visitor.leaf(ids, m),
            #[cfg(target_arch = "x86_64")]
            // SAFETY: a `Kind::Avx2` token is only made by `LeafIsa::avx2`,
            // whose caller promised that this CPU supports AVX2.
            Kind::Avx2 => unsafe { leaf_avx2(visitor, ids, m) },
            #[cfg(target_arch = "x86_64")]
            // SAFETY: a `Kind::Avx512` token is only made by
            // `LeafIsa::avx512`, whose caller promised the four features.
            Kind::Avx512 => unsafe { leaf_avx512(visitor, ids, m) },
        }
    }
}

/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[inline(never)]
#[target_feature(enable = "avx2")]
unsafe fn leaf_avx2<S, const W: usize, V: LeafVisitor<S, W>>(visitor: &mut V, ids: &[u32], m: Mask<W>) {
    visitor.leaf_inlined(ids, m)
}

/// # Safety
/// The CPU must support AVX-512 F, VL, BW and DQ.
#[cfg(target_arch = "x86_64")]
#[inline(never)]
#[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512dq")]
unsafe fn leaf_avx512<S, const W: usize, V: LeafVisitor<S, W>>(visitor: &mut V, ids: &[u32], m: Mask<W>) {
    visitor.leaf_inlined(ids, m)
}
