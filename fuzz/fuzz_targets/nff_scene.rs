//! Arbitrary bytes into the NFF reader and the scene builder: the scanner and
//! the reader (into a deliberately small scene, so capacity errors happen),
//! then `raypack::image::with_scene` for both scalars, the path the command
//! line loads a file through (size tier, fixed-point conversion, BVH).
//!
//! Never a panic; errors are fine, but they must agree: the scanner and the
//! reader report the same error (except capacity, which only the reader
//! has, and which may come first), a success builds exactly the counted scene, and a file the scanner
//! accepts loads in `f32`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use raypack::image::{self, AccelKind, Error, ScalarKind};
use raypack::nff::{self, NffErrorKind};
use raypack::scene::Scene;

fuzz_target!(|data: &[u8]| {
    // Bounded input: a 4 KB file holds at most a few hundred entities.
    if data.len() > 4096 {
        return;
    }
    let text = String::from_utf8_lossy(data);
    let scanned = nff::scan(&text);
    let mut small: Scene<f32, 32, 128, 8, 4> = Scene::new();
    let parsed = nff::parse(&text, &mut small);
    match (&scanned, &parsed) {
        (Ok(a), Ok(b)) => {
            assert_eq!(a, b);
            assert_eq!(small.len(), a.counts.primitives());
            assert_eq!(small.vertex_count(), a.counts.vertices);
        }
        // The reader stops at its first error: a capacity error may come
        // before the scanner's.
        (Err(a), Err(b)) if matches!(b.kind, NffErrorKind::Capacity(_)) => assert!(a.line >= b.line, "{a} / {b}"),
        (Err(a), Err(b)) => assert_eq!(a, b),
        (Ok(_), Err(e)) => assert!(matches!(e.kind, NffErrorKind::Capacity(_)), "{e}"),
        (Err(e), Ok(_)) => panic!("only the scanner failed: {e}"),
    }
    if let Err(e) = &parsed {
        assert!(e.line >= 1 && e.column >= 1, "{e:?}");
        assert!(e.to_string().starts_with(&format!("line {}, column {}: ", e.line, e.column)));
    }

    for scalar in [ScalarKind::F32, ScalarKind::Fixed32] {
        let loaded = image::with_scene(&text, scalar, AccelKind::Bvh, |s| {
            let _ = s.bounds();
            *s.info()
        });
        match (&scanned, loaded) {
            (Ok(a), Ok(info)) => {
                assert_eq!(info.nff, *a);
                assert_eq!(info.scalar, scalar);
                let bvh = info.bvh.expect("a tree was asked for").0;
                assert_eq!(bvh.primitives as usize, a.counts.primitives());
            }
            (Err(a), Err(Error::Scene(b))) => assert_eq!(*a, b),
            (Err(a), r) => panic!("the scanner failed ({a}) but with_scene gave {:?}", r.map(|_| ())),
            (Ok(_), Err(e)) => {
                // Only the fixed-point conversion may fail on a valid file
                // (a 4 KB file fits the smallest tiers, and every tier has
                // room for its tree).
                assert!(scalar == ScalarKind::Fixed32 && matches!(e, Error::Convert(_) | Error::Scene(_)), "{scalar:?}: {e}");
                let _ = e.to_string();
            }
        }
    }
});
