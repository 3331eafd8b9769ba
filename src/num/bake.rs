//! The [`Bake`] trait: values that write themselves as Rust constant
//! expressions, for scenes baked on a host into `static` data (see
//! `raypack::scene::bake`, which writes whole scenes). Here are the trait,
//! its impls for `f32` and plain values (the fixed-point scalars implement
//! it in their own modules), and the macro that gives a
//! struct of private fields a `const fn from_baked` and its [`Bake`]; each
//! type invokes the macro in its own module.

use core::fmt::{self, Write};

/// A value that can write itself as a Rust constant expression which
/// rebuilds it exactly (paths from the crate root, `raypack::…`).
pub trait Bake {
    /// Writes the expression.
    fn bake(&self, w: &mut dyn Write) -> fmt::Result;
}

impl Bake for f32 {
    /// `f32::from_bits(…)`: every value exactly, NaN payloads and `-0.0`
    /// included.
    fn bake(&self, w: &mut dyn Write) -> fmt::Result {
        write!(w, "f32::from_bits({:#010x})", self.to_bits())
    }
}
macro_rules! bake_display {
    ($($t:ty),*) => {$(
        impl Bake for $t {
            fn bake(&self, w: &mut dyn Write) -> fmt::Result {
                write!(w, "{}", self)
            }
        }
    )*};
}
bake_display!(bool, u8, u16, u32);

impl<T: Bake, const N: usize> Bake for [T; N] {
    fn bake(&self, w: &mut dyn Write) -> fmt::Result {
        list(w, "[", self.iter().map(|v| v as &dyn Bake), "]")
    }
}

impl<T: Bake> Bake for Option<T> {
    fn bake(&self, w: &mut dyn Write) -> fmt::Result {
        match self {
            None => w.write_str("None"),
            Some(v) => call(w, "Some", &[v]),
        }
    }
}

impl<A: Bake, B: Bake> Bake for (A, B) {
    fn bake(&self, w: &mut dyn Write) -> fmt::Result {
        list(w, "(", [&self.0 as &dyn Bake, &self.1], ")")
    }
}

/// Writes `open`, the items baked and separated by `, `, then `close`.
fn list<'a>(w: &mut dyn Write, open: &str, items: impl IntoIterator<Item = &'a dyn Bake>, close: &str) -> fmt::Result {
    w.write_str(open)?;
    for (i, v) in items.into_iter().enumerate() {
        if i > 0 {
            w.write_str(", ")?;
        }
        v.bake(w)?;
    }
    w.write_str(close)
}

/// Writes `name(a, b, …)` with each argument baked.
#[doc(hidden)]
pub fn call(w: &mut dyn Write, name: &str, args: &[&dyn Bake]) -> fmt::Result {
    w.write_str(name)?;
    list(w, "(", args.iter().copied(), ")")
}

/// Gives a struct a `const fn from_baked` taking every field in order, and
/// a [`Bake`] that writes a call of it with the fields' values. Invoked in
/// each type's own module (the fields are private there).
macro_rules! bake_struct {
    ($path:literal, $ty:ident < $s:ident > { $($f:ident : $t:ty),* $(,)? }) => {
        impl<$s> $ty<$s> {
            /// Rebuilds the value from its fields, in declaration order, as
            /// [`Bake`](crate::num::bake::Bake) wrote them (scenes baked
            /// into `static` data, see `raypack::scene::bake`). Unchecked:
            /// other values give unspecified answers, never a panic.
            #[allow(clippy::too_many_arguments)]
            pub const fn from_baked($($f: $t),*) -> Self {
                $ty { $($f),* }
            }
        }
        impl<$s: $crate::num::bake::Bake> $crate::num::bake::Bake for $ty<$s> {
            fn bake(&self, w: &mut dyn core::fmt::Write) -> core::fmt::Result {
                $crate::num::bake::call(w, concat!($path, "::from_baked"), &[$(&self.$f),*])
            }
        }
    };
}
pub(crate) use bake_struct;
