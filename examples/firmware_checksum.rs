//! Prints the host's checksums of the firmware scene (the demo scene at
//! 160×128), in the format of `targets/checksums.txt`; `scripts/firmware.sh`
//! compares them with the recorded values and with each board's output.
//!
//! `cargo run --example firmware_checksum`
use raypack::demo::{demo_camera, demo_scene};
use raypack::prelude::*;

fn main() -> Result<(), String> {
    let scene = demo_scene::<f32>().map_err(|e| e.to_string())?;
    let camera = demo_camera::<f32>(160, 128).map_err(|e| e.to_string())?;
    let tracer: Tracer<f32> = Tracer::new(scene.view(), TraceSettings::default()).map_err(|e| e.to_string())?;
    let renderer = Renderer::new(tracer, camera);
    let mut band = vec![[0u8; 3]; 160 * 2];
    let c = renderer.checksums::<8>(&mut band).map_err(|e| e.to_string())?;
    println!("f32 rgb888 {:#010x}", c.rgb888);
    println!("f32 rgb565-bayer4 {:#010x}", c.rgb565);
    println!("f32 rays {}", c.rays.total());
    Ok(())
}
