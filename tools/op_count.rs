//! Counts the scalar operations of one firmware frame (the demo scene at
//! 160×128, one ray at a time, as the Cortex-M0 board renders it) for `f32`
//! and for `Fixed32`, by rendering through a scalar that wraps each one and
//! counts every operation: what an FPU-less core pays per frame is roughly
//! the sum of count × cost per operation (soft-float calls for `f32`,
//! inline integer code or calls for `Fixed32`; see `src/num/fixed32.rs` for the
//! measured cost of each).
//!
//! `cargo run --release --example op_count`
use core::ops::{Add, Div, Mul, Neg, Sub};
use raypack::demo::{build_demo_scene_for, demo_camera_for, DemoScene};
use raypack::prelude::*;
use raypack::Fixed32;
use std::cell::Cell;

const OPS: [&str; 9] = ["add/sub", "mul", "div", "sqrt", "powf", "compare", "neg/abs", "from/to", "ratio"];
thread_local! {
    static COUNT: [Cell<u64>; 9] = Default::default();
}
fn tick(op: usize) {
    COUNT.with(|c| c[op].set(c[op].get() + 1));
}

#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Counted<S>(S);

impl<S: Scalar> PartialOrd for Counted<S> {
    fn partial_cmp(&self, o: &Self) -> Option<core::cmp::Ordering> {
        tick(5);
        self.0.partial_cmp(&o.0)
    }
}
macro_rules! op {
    ($tr:ident, $f:ident, $i:expr) => {
        impl<S: Scalar> $tr for Counted<S> {
            type Output = Self;
            fn $f(self, o: Self) -> Self {
                tick($i);
                Counted(self.0.$f(o.0))
            }
        }
    };
}
op!(Add, add, 0);
op!(Sub, sub, 0);
op!(Mul, mul, 1);
op!(Div, div, 2);
impl<S: Scalar> Neg for Counted<S> {
    type Output = Self;
    fn neg(self) -> Self {
        tick(6);
        Counted(-self.0)
    }
}

impl<S: Scalar> Scalar for Counted<S> {
    const ZERO: Self = Counted(S::ZERO);
    const ONE: Self = Counted(S::ONE);
    const HALF: Self = Counted(S::HALF);
    const TWO: Self = Counted(S::TWO);
    const MAX: Self = Counted(S::MAX);
    const RAY_EPSILON: Self = Counted(S::RAY_EPSILON);
    const MIN_WEIGHT: Self = Counted(S::MIN_WEIGHT);
    const LIMITED_RANGE: bool = S::LIMITED_RANGE;
    const COORDINATE_LIMIT: f32 = S::COORDINATE_LIMIT;
    const LIGHT_LIMIT: f32 = S::LIGHT_LIMIT;
    const INTERMEDIATE_LIMIT: f32 = S::INTERMEDIATE_LIMIT;
    const SCENE_FRAME: Option<f32> = S::SCENE_FRAME;
    const NORMALIZE_PRESCALE: bool = S::NORMALIZE_PRESCALE;
    fn normalizing_factor(self) -> Self {
        Counted(self.0.normalizing_factor())
    }
    fn ratio(num: u32, den: u32) -> Self {
        tick(8);
        Counted(S::ratio(num, den))
    }
    fn from_f32(v: f32) -> Self {
        tick(7);
        Counted(S::from_f32(v))
    }
    fn from_i32(v: i32) -> Self {
        tick(7);
        Counted(S::from_i32(v))
    }
    fn to_f32(self) -> f32 {
        tick(7);
        self.0.to_f32()
    }
    fn sqrt(self) -> Self {
        tick(3);
        Counted(self.0.sqrt())
    }
    fn powf(self, e: Self) -> Self {
        tick(4);
        Counted(self.0.powf(e.0))
    }
    fn floor_to_i32(self) -> i32 {
        self.0.floor_to_i32()
    }
    fn is_finite(self) -> bool {
        self.0.is_finite()
    }
    fn abs(self) -> Self {
        tick(6);
        Counted(self.0.abs())
    }
    fn min(self, o: Self) -> Self {
        tick(5);
        Counted(self.0.min(o.0))
    }
    fn max(self, o: Self) -> Self {
        tick(5);
        Counted(self.0.max(o.0))
    }
    fn to_unorm8(self) -> u8 {
        self.0.to_unorm8()
    }
}

fn frame<S: Scalar>(name: &str) {
    let mut scene = Box::new(DemoScene::<Counted<S>>::new());
    let mut described = Box::new(DemoScene::<f32>::new());
    let frame = build_demo_scene_for(&mut scene, &mut described).unwrap();
    let camera = demo_camera_for::<Counted<S>>(&frame, 160, 128).unwrap();
    let renderer = Renderer::new(Tracer::<Counted<S>>::new(scene.view(), TraceSettings::default()).unwrap(), camera);
    COUNT.with(|c| c.iter().for_each(|x| x.set(0)));
    let mut img = vec![[0u8; 3]; 160 * 128];
    let mut stats = RayStats::default();
    renderer.render_rect::<1>(camera.full_rect(), &mut img, &mut stats).unwrap();
    let counts: Vec<u64> = COUNT.with(|c| c.iter().map(Cell::get).collect());
    println!("{name}: {} rays", stats.total());
    for (op, n) in OPS.iter().zip(&counts) {
        println!("  {op:8} {n:>11} ({:.1} per ray)", *n as f64 / stats.total() as f64);
    }
}

fn main() {
    frame::<f32>("f32");
    frame::<Fixed32>("fixed32");
}
