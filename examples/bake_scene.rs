//! Bakes the firmware's demo scene (Q8.24 `Fixed32`, in its frame, with the
//! camera for a 160×128 image) into Rust source on standard output: the
//! `static` arrays and camera that `targets/common/src/baked_demo.rs` holds,
//! which the `fixed32`-only `microbit` image renders without building a
//! scene (see `raypack::scene::bake` and docs/firmware.md).
//!
//! ```sh
//! cargo run --example bake_scene > targets/common/src/baked_demo.rs
//! cargo run --example bake_scene -- 240 135    # another image size
//! ```
//!
//! Bake your own scene the same way: build it on the host as usual (for the
//! scalar the firmware renders with), make its camera, and call
//! `bake_scene` on the view.

use raypack::demo::{build_demo_scene_for, demo_camera_for, DemoScene};
use raypack::scene::bake::bake_scene;
use raypack::Fixed32;

fn main() {
    let args: Vec<u32> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    let (width, height) = match args[..] {
        [w, h] => (w, h),
        _ => (160, 128),
    };
    let mut scene = Box::new(DemoScene::<Fixed32>::new());
    let mut described = Box::new(DemoScene::<f32>::new());
    let frame = build_demo_scene_for(&mut scene, &mut described).expect("the demo scene fits its capacities");
    let camera = demo_camera_for::<Fixed32>(&frame, width, height).expect("a valid camera for that size");
    let mut source = String::new();
    bake_scene(&scene.view(), &camera, &mut source).expect("writing to a String");
    print!("{source}");
}
