//! Tracing: the Whitted integrator and plain ray casting over packets of any
//! width, on top of the queries of [`crate::query`].

mod tracer;

pub use tracer::{Mode, RayStats, SurfacePacket, TraceError, TraceSettings, Tracer};
