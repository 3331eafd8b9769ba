//! What every Arm QEMU board does over semihosting (`-semihosting-config
//! enable=on`): its console, its exit with success or failure, and its
//! exception and panic handlers, which report `result=FAILED …` and exit.
//! A board defines the handlers with [`arm_handlers!`](crate::arm_handlers).

use crate::Console;
use cortex_m_semihosting::{debug, hio};

/// Semihosting standard output (writes nothing if the host gave none).
pub struct Semihosting(Option<hio::HostStream>);

impl Console for Semihosting {
    fn write_str(&mut self, s: &str) {
        if let Some(out) = self.0.as_mut() {
            let _ = out.write_all(s.as_bytes());
        }
    }
}

/// The host's standard output.
pub fn console() -> Semihosting {
    Semihosting(hio::hstdout().ok())
}

/// Ends the QEMU run with success or failure as its exit status.
pub fn exit(ok: bool) -> ! {
    debug::exit(if ok { debug::EXIT_SUCCESS } else { debug::EXIT_FAILURE });
    loop {
        cortex_m::asm::bkpt();
    }
}

/// A hard fault at `pc`: reported, then a failed exit.
pub fn hard_fault(pc: u32) -> ! {
    let mut con = console();
    con.write_str("result=FAILED HardFault at pc=");
    con.write_hex32(pc);
    con.write_str("\n");
    exit(false)
}

/// An exception no handler expects (`irqn` as cortex-m-rt's
/// `DefaultHandler` gives it): reported, then a failed exit.
pub fn unexpected_exception(irqn: i16) -> ! {
    let mut con = console();
    con.write_str("result=FAILED unexpected exception ");
    con.write_u32(irqn as u16 as u32);
    con.write_str("\n");
    exit(false)
}

/// A panic: reported, then a failed exit.
pub fn panicked() -> ! {
    let mut con = console();
    con.write_str("result=FAILED panic\n");
    exit(false)
}

/// Defines a board's exception handlers (cortex-m-rt's `#[exception]`
/// items must be in the binary crate): `SysTick` counts the clock's wraps
/// ([`crate::timing::systick::on_wrap`]), `HardFault` and `DefaultHandler`
/// report and exit ([`hard_fault`], [`unexpected_exception`]); and, unless
/// the board's feature `panic-never` is on, the panic handler
/// ([`panicked`]). The board depends on `cortex-m-rt`.
#[macro_export]
macro_rules! arm_handlers {
    () => {
        /// Counts SysTick wraps for the frame-time clock.
        #[cortex_m_rt::exception]
        fn SysTick() {
            $crate::timing::systick::on_wrap();
        }

        #[cortex_m_rt::exception]
        unsafe fn HardFault(frame: &cortex_m_rt::ExceptionFrame) -> ! {
            $crate::semihosting::hard_fault(frame.pc())
        }

        #[cortex_m_rt::exception]
        unsafe fn DefaultHandler(irqn: i16) {
            $crate::semihosting::unexpected_exception(irqn)
        }

        #[cfg(not(feature = "panic-never"))]
        #[panic_handler]
        fn panic(_: &core::panic::PanicInfo) -> ! {
            $crate::semihosting::panicked()
        }
    };
}
