//! Fixed point against `f32` on scene files: PSNR of the colour image and
//! ID-AOV agreement, through `raypack::image` (BVH, packets of 8, all cores).
//!
//! `cargo run --release --example fixed_quality -- SIZE fixed32 FILE...`
use raypack::image::{Image, Options, ScalarKind};
use raypack::render::{Aov, Rgb8};

fn psnr(a: &[Rgb8], b: &[Rgb8]) -> f64 {
    let se: f64 = a.iter().zip(b).map(|(p, q)| (0..3).map(|c| (p[c] as f64 - q[c] as f64).powi(2)).sum::<f64>()).sum();
    let mse = se / (3 * a.len()) as f64;
    if mse == 0.0 {
        f64::INFINITY
    } else {
        10.0 * (255.0 * 255.0 / mse).log10()
    }
}

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let size: u32 = a.get(1).and_then(|s| s.parse().ok()).unwrap_or(256);
    let scalar = ScalarKind::Fixed32;
    for path in a.iter().skip(3) {
        let text = std::fs::read_to_string(path).unwrap();
        let base = Options { width: Some(size), height: Some(size), ..Options::default() };
        let run = |scalar, aov| {
            let t = std::time::Instant::now();
            let r = Image::render(&text, &Options { scalar, aov, ..base }).map(|i| i.pixels);
            (r, t.elapsed().as_secs_f64())
        };
        let (cf, tf) = run(ScalarKind::F32, Aov::Color);
        let (cx, tx) = run(scalar, Aov::Color);
        let (idf, _) = run(ScalarKind::F32, Aov::Id);
        let (idx, _) = run(scalar, Aov::Id);
        match (cf, cx, idf, idx) {
            (Ok(cf), Ok(cx), Ok(idf), Ok(idx)) => {
                let agree = idf.iter().zip(&idx).filter(|(p, q)| p == q).count() as f64 / idf.len() as f64;
                println!(
                    "{path:40} PSNR {:7.2} dB  ID {:8.4} %  time f32 {tf:.3} s {} {tx:.3} s",
                    psnr(&cf, &cx),
                    agree * 100.0,
                    scalar.name()
                );
            }
            (a, b, c, d) => println!(
                "{path}: error {:?}",
                [a.err(), b.err(), c.err(), d.err()].iter().flatten().next().map(|e| e.to_string())
            ),
        }
    }
}
