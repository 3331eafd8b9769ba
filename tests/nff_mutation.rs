//! Seeded mutations of every scene file in `tests/scenes/` (the 17 SPD
//! databases and the extension sample) through the NFF reader and the scene
//! builder of the command line (`raypack::image::with_scene`: heap scene,
//! fixed-point conversion, BVH), a few of them rendered as tiny images.
//!
//! Deterministic: the suite's SplitMix64 generator (`tests/common`) with a fixed seed makes the same
//! inputs on every run (see [`MUTANTS`] and [`SEED`]; docs/fuzzing.md).
//! Each input is one to three of: a line deleted, duplicated or swapped
//! with another; a number replaced by NaN, an infinity, -0, 1e39, a huge or
//! tiny value or garbage; the file cut mid-line; a field dropped; random
//! characters inserted (control characters, non-ASCII white space,
//! multi-byte letters); a keyword letter changed.
//!
//! For each: no panic, and
//! - a file the reader accepts loads, and the loaded scene reports what the
//!   scanner counted;
//! - a rejection is the reader's error (the same as the scanner's) and its
//!   message names its line ("line N, column M: ..."), a line of the text;
//! - the only rejections without a line are the whole-scene ones, by
//!   variant (see [`whole_file_reason`]).

mod common;

use common::{Rng, SCENES};
use raypack::dispatch::Isa;
use raypack::image::{self, AccelKind, Error, Options, ScalarKind};
use raypack::nff;
use raypack::render::Sampling;
use raypack::trace::Mode;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// The generator's seed.
const SEED: u64 = 0x6e66_665f_6d75_7461; // "nff_muta"

/// Mutated inputs: per file, by size (large files cost more per read in a
/// debug build), so that the whole test stays within a few seconds.
fn mutants_of(text: &str) -> usize {
    match text.len() {
        0..=8_192 => 500,
        8_193..=40_000 => 100,
        _ => 15,
    }
}

/// The total: 13 files up to 8 KB, 3 up to 40 KB, 2 larger (checked by the
/// test, so a change of the mix is deliberate).
const MUTANTS: usize = 13 * 500 + 3 * 100 + 2 * 15;

/// One of `items`, uniformly.
fn pick<'a, T>(rng: &mut Rng, items: &'a [T]) -> &'a T {
    &items[rng.below(items.len() as u32) as usize]
}

/// Replacements for a number field.
const ODD_NUMBERS: &[&str] = &[
    "NaN",
    "nan",
    "inf",
    "-inf",
    "infinity",
    "-0",
    "0",
    "-0.0",
    "1e39",
    "-1e39",
    "3.4028235e38",
    "3.4028236e38",
    "1e30",
    "-1e30",
    "99999999999999999999999",
    "1e-45",
    "1e-50",
    "65535",
    "65536",
    "4294967296",
    "-1",
    "2",
    "1.2.3",
    "0x10",
    "1e",
    "--1",
    "+",
    ".",
    "1,5",
    "é",
    "٣",
    "１",
];

/// Characters to insert: separators the reader does and does not treat as
/// white space, line ends, comment marks, letters of several widths.
const ODD_CHARS: &[char] = &[
    ' ', '\t', '\n', '\r', '\u{b}', '\u{c}', '\0', '#', '-', '.', 'e', '0', '9', 'p', 'v', 'é', '\u{a0}', '\u{2028}',
    '\u{feff}', '€', '𝔁', '\u{7f}',
];

/// A mutation of `text`, described for the failure message.
fn mutate(rng: &mut Rng, text: &str) -> (String, Vec<&'static str>) {
    let mut lines: Vec<String> = text.split('\n').map(str::to_owned).collect();
    let mut ops = Vec::new();
    for _ in 0..1 + rng.below(3) as usize {
        let n = lines.len();
        let at = rng.below(n as u32) as usize;
        match rng.below(9) as usize {
            0 => {
                ops.push("delete a line");
                if n > 1 {
                    lines.remove(at);
                }
            }
            1 => {
                ops.push("duplicate a line");
                let l = lines[at].clone();
                lines.insert(at, l);
            }
            2 => {
                ops.push("swap two lines");
                let other = rng.below(n as u32) as usize;
                lines.swap(at, other);
            }
            3 | 4 => {
                ops.push("replace a number");
                let fields = field_spans(&lines[at]);
                // Numbers are the fields after the keyword (or all fields of
                // a continuation line); any field will do.
                if !fields.is_empty() {
                    let (s, e) = *pick(rng, &fields);
                    let odd = *pick(rng, ODD_NUMBERS);
                    lines[at].replace_range(s..e, odd);
                }
            }
            5 => {
                ops.push("truncate mid-line");
                lines.truncate(at + 1);
                let l = &mut lines[at];
                let mut cut = rng.below((l.len() + 1) as u32) as usize;
                while !l.is_char_boundary(cut) {
                    cut -= 1;
                }
                l.truncate(cut);
            }
            6 => {
                ops.push("drop a field");
                let fields = field_spans(&lines[at]);
                if !fields.is_empty() {
                    let (s, e) = *pick(rng, &fields);
                    lines[at].replace_range(s..e, "");
                }
            }
            7 => {
                ops.push("insert characters");
                let l = &mut lines[at];
                for _ in 0..1 + rng.below(3) as usize {
                    let mut pos = rng.below((l.len() + 1) as u32) as usize;
                    while !l.is_char_boundary(pos) {
                        pos -= 1;
                    }
                    l.insert(pos, *pick(rng, ODD_CHARS));
                }
            }
            _ => {
                ops.push("change a keyword letter");
                if let Some(&(s, e)) = field_spans(&lines[at]).first() {
                    let word: Vec<char> = lines[at][s..e].chars().collect();
                    let k = rng.below(word.len() as u32) as usize;
                    let mut word = word;
                    word[k] = match rng.below(3) as usize {
                        0 => word[k].to_ascii_uppercase(),
                        1 => (b'a' + rng.below(26) as u8) as char,
                        _ => *pick(rng, &['x', 'q', 'f', 'p', 's', 'l']),
                    };
                    let word: String = word.into_iter().collect();
                    lines[at].replace_range(s..e, &word);
                }
            }
        }
    }
    (lines.join("\n"), ops)
}

/// Byte ranges of the white-space separated fields of `line` (the reader's
/// ASCII white space).
fn field_spans(line: &str) -> Vec<(usize, usize)> {
    let b = line.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        while i < b.len() && b[i].is_ascii_whitespace() {
            i += 1;
        }
        let s = i;
        while i < b.len() && !b[i].is_ascii_whitespace() {
            i += 1;
        }
        if i > s {
            out.push((s, i));
        }
    }
    out
}

/// The rejections that name no line, and why that is right: they are about
/// the whole scene, found after the whole file was read, when lines are
/// gone (the scene keeps primitive and light indices, which the messages
/// name instead).
fn whole_file_reason(e: &Error) -> bool {
    match e {
        // The file has no `v` block at all: there is no line to point at.
        Error::NoCamera => true,
        // Fixed point: the scene is fitted into the scalar's small frame
        // from its bounding box (all primitives and the eye), then copied
        // over; a primitive or light that does not fit that frame is named
        // by its index ("primitive k", "light k").
        Error::Convert(_) => true,
        // Fixed point, at render time: the camera in the fitted frame, and
        // the whole-scene range check (indices again).
        Error::Camera(_) | Error::Range(_) => true,
        // The reader's errors all have a line; a scene built from a file
        // never overflows its size tier (chosen from the scanner's counts)
        // or its tree (sized like the tier); the options are fixed here.
        _ => false,
    }
}

/// The tiny render of a subset of the inputs.
fn tiny(scalar: ScalarKind) -> Options {
    Options {
        width: Some(6),
        height: Some(4),
        packet: 4,
        threads: Some(1),
        mode: Mode::Whitted,
        depth: 2,
        scalar,
        isa: Isa::best(),
        sampling: Sampling::Centre,
        ..Options::default()
    }
}

/// The variant name of an error, for the tally the test prints.
fn variant(e: &Error) -> String {
    let d = match e {
        Error::Scene(n) => format!("{:?}", n.kind),
        other => format!("{other:?}"),
    };
    d.split(|c: char| !c.is_alphanumeric()).next().unwrap_or("").to_owned()
}

/// Checks one input; panics (with what went wrong) on a violation; returns
/// the error's variant name if it was rejected (for the tally).
fn check(text: &str, scalar: ScalarKind, accel: AccelKind, render: bool) -> Option<String> {
    let scanned = nff::scan(text);
    let loaded = image::with_scene(text, scalar, accel, |s| {
        let image = render.then(|| s.render(&tiny(scalar), &|| {}));
        (*s.info(), image)
    });
    let lines = text.split('\n').count() as u32;
    let named = |e: &Error| {
        let Error::Scene(n) = e else { return false };
        let msg = e.to_string();
        n.line >= 1 && n.line <= lines + 1 && msg.starts_with(&format!("line {}, column {}: ", n.line, n.column))
    };
    match (&scanned, loaded) {
        (Ok(counted), Ok((info, image))) => {
            assert_eq!(info.nff, *counted, "the loaded scene differs from the scan");
            assert_eq!(info.scalar, scalar);
            if let Some(image) = image {
                match image {
                    Ok(img) => assert_eq!((img.width, img.height, img.pixels.len()), (6, 4, 24)),
                    Err(e) => {
                        assert!(whole_file_reason(&e), "render error without a line: {e:?} ({e})");
                        return Some(format!("render: {}", variant(&e)));
                    }
                }
            }
            None
        }
        (Err(a), Err(e)) => {
            assert!(matches!(&e, Error::Scene(b) if b == a), "the scanner says {a}, with_scene says {e}");
            assert!(named(&e), "no line in {e:?} ({e}), text has {lines} lines");
            Some(variant(&e))
        }
        (Err(a), Ok(_)) => panic!("the scanner rejects ({a}) what with_scene loads"),
        (Ok(_), Err(e)) => {
            assert!(scalar == ScalarKind::Fixed32, "an f32 load failed on a file the scanner accepts: {e}");
            assert!(named(&e) || whole_file_reason(&e), "no line in {e:?} ({e})");
            assert!(!e.to_string().is_empty());
            Some(format!("fixed32: {}", variant(&e)))
        }
    }
}

#[test]
fn mutated_scenes_load_or_fail_with_a_line_number() {
    let mut rng = Rng(SEED);
    let (mut count, mut rejected, mut rendered) = (0usize, 0usize, 0usize);
    let mut tally = std::collections::BTreeMap::<String, usize>::new();
    for (name, source) in SCENES {
        for k in 0..mutants_of(source) {
            let (text, ops) = mutate(&mut rng, source);
            // Every input in f32 (brute force for the large files: the tree
            // costs more than the reading in a debug build); every fourth
            // again in fixed point; every 24th rendered too.
            let small = source.len() <= 8_192;
            let accel = if small { AccelKind::Bvh } else { AccelKind::BruteForce };
            let render = small && k % 24 == 0;
            for scalar in [ScalarKind::F32, ScalarKind::Fixed32] {
                if scalar == ScalarKind::Fixed32 && k % 4 != 0 {
                    continue;
                }
                match catch_unwind(AssertUnwindSafe(|| check(&text, scalar, accel, render))) {
                    Ok(Some(v)) => *tally.entry(v).or_default() += 1,
                    Ok(None) => {}
                    Err(p) => {
                        let why = p
                            .downcast_ref::<String>()
                            .map(String::as_str)
                            .or(p.downcast_ref::<&str>().copied())
                            .unwrap_or("?");
                        panic!("{name} mutant {k} ({ops:?}, {scalar:?}): {why}\n--- input ---\n{text}");
                    }
                }
            }
            rejected += nff::scan(&text).is_err() as usize;
            rendered += render as usize;
            count += 1;
        }
    }
    assert_eq!(count, MUTANTS);
    // The mix exercises both sides: most mutants are rejected, some not.
    println!("{count} mutants: {rejected} rejected by the reader, {} accepted, {rendered} rendered", count - rejected);
    for (v, n) in &tally {
        println!("{n:6} {v}");
    }
    assert!(rejected > count / 3 && rejected < count, "{rejected} of {count} rejected");
}
