//! Prints the host's checksums of the firmware scene (the demo scene at
//! 160×128) for `f32` and for the Q8.24 [`Fixed32`] scalar (its scene built
//! in `f32` and converted into its frame, as the firmware does), in the
//! format of `targets/checksums.txt`; `scripts/firmware.sh` compares them
//! with the recorded values and with each board's output.
//!
//! `cargo run --example firmware_checksum`
use raypack::demo::{build_demo_scene_for, demo_camera_for, DemoScene};
use raypack::output::ImageChecksums;
use raypack::prelude::*;
use raypack::Fixed32;

fn checksums<S: Scalar>() -> Result<ImageChecksums, String> {
    let mut scene = Box::new(DemoScene::<S>::new());
    let mut described = Box::new(DemoScene::<f32>::new());
    let frame = build_demo_scene_for(&mut scene, &mut described).map_err(|e| e.to_string())?;
    let camera = demo_camera_for::<S>(&frame, 160, 128).map_err(|e| e.to_string())?;
    let tracer: Tracer<S> = Tracer::new(scene.view(), TraceSettings::default()).map_err(|e| e.to_string())?;
    let renderer = Renderer::new(tracer, camera);
    let mut band = vec![[0u8; 3]; 160 * 2];
    renderer.checksums::<8>(&mut band).map_err(|e| e.to_string())
}

fn main() -> Result<(), String> {
    for (name, c) in [("f32", checksums::<f32>()?), ("fixed32", checksums::<Fixed32>()?)] {
        println!("{name} rgb888 {:#010x}", c.rgb888);
        println!("{name} rgb565-bayer4 {:#010x}", c.rgb565);
        println!("{name} rays {}", c.rays.total());
    }
    Ok(())
}
