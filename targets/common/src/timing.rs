//! Frame time as a count of instructions (under QEMU) or of microseconds
//! (on a real board): a [`Clock`] that counts ticks of a timer, the rate of
//! its ticks ([`TickRate`]), and [`measure`], which runs a closure between
//! two readings.
//!
//! Under `qemu-system-* -icount shift=0` QEMU's virtual clock advances
//! exactly 1 ns per guest instruction retired (2^`shift` ns per
//! instruction), and every timer QEMU models (the Arm SysTick, the RISC-V
//! CLINT's `mtime`) counts that virtual time. So a timer of `f` Hz ticks once
//! per `10⁹ / f` instructions, and [`TickRate::instructions`] turns ticks
//! back into instructions, to within one tick (the conversion's resolution,
//! [`TickRate::resolution`]). The count is deterministic: the same program
//! retires the same instructions, and the timer interrupts fall at the same
//! instruction every run.
//!
//! `calibrate` (on the firmware targets) checks that assumption on the
//! board itself: it times a loop of a known number of instructions and
//! compares.

/// A timer that counts up from an arbitrary origin, in ticks of its
/// [`TickRate`], without wrapping within any measurement (64 bits).
pub trait Clock {
    /// Ticks since the clock's origin.
    fn now(&mut self) -> u64;
    /// How fast the clock ticks.
    fn rate(&self) -> TickRate;
}

/// Runs `f` between two readings of `clock`; returns its result and the
/// ticks that passed.
#[inline(never)]
pub fn measure<C: Clock, R>(clock: &mut C, f: impl FnOnce() -> R) -> (R, u64) {
    let start = clock.now();
    let r = f();
    let end = clock.now();
    (r, end.wrapping_sub(start))
}

/// The nanoseconds one tick lasts, as a reduced fraction `num / den`, and
/// the frequency it came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TickRate {
    hz: u32,
    num: u64,
    den: u64,
}

/// `n / d` and `n % d`, rounded down, by binary long division (one
/// shift, compare and subtract per quotient bit); `(u64::MAX, n)` for
/// `d == 0`. Armv6-M's 64-bit `/` and `%` are a library routine of some
/// 900 bytes of flash (`u64_div_rem`); these conversions run only around
/// a frame and its bands, so a loop of 152 bytes does instead (see
/// `div_rem` for where it is used).
#[inline(never)]
pub const fn div_rem_u64(n: u64, d: u64) -> (u64, u64) {
    if d == 0 {
        return (u64::MAX, n);
    }
    let (mut q, mut r) = (0u64, 0u64);
    let mut bit = 64;
    while bit > 0 {
        bit -= 1;
        // r < d here, so r·2 + 1 < 2d fits whenever d does not use the top
        // bit; with it, the bit shifted out of r means r·2 ≥ 2^64 > d.
        let carry = r >> 63;
        r = (r << 1) | ((n >> bit) & 1);
        if carry != 0 || r >= d {
            r = r.wrapping_sub(d);
            q |= 1 << bit;
        }
    }
    (q, r)
}

/// `n / d` and `n % d` as the firmware computes them (`(u64::MAX, n)` for
/// `d == 0`): by [`div_rem_u64`] on Arm, which takes 750–860 bytes off
/// the Armv6-M images; with `/` and `%` on RISC-V, where the timer's rate
/// is a constant, the divisions fold away when the image is compiled, and
/// the loop (out of line, so it cannot fold) made the image 736 bytes
/// larger.
const fn div_rem(n: u64, d: u64) -> (u64, u64) {
    if cfg!(target_arch = "riscv32") {
        match (n.checked_div(d), n.checked_rem(d)) {
            (Some(q), Some(r)) => (q, r),
            _ => (u64::MAX, n),
        }
    } else {
        div_rem_u64(n, d)
    }
}

/// Greatest common divisor (Euclid), for `const` contexts.
const fn gcd(mut a: u64, mut b: u64) -> u64 {
    while b != 0 {
        let t = div_rem(a, b).1;
        a = b;
        b = t;
    }
    a
}

/// Nanoseconds per second.
pub const NANOS_PER_SECOND: u64 = 1_000_000_000;

impl TickRate {
    /// A timer ticking at `hz` (a frequency of 0 is taken as 1 Hz, so that
    /// no conversion ever divides by zero).
    pub const fn from_hz(hz: u32) -> Self {
        let hz = if hz == 0 { 1 } else { hz };
        let g = gcd(NANOS_PER_SECOND, hz as u64);
        // `g` divides both exactly and is at least 1.
        TickRate { hz, num: div_rem(NANOS_PER_SECOND, g).0, den: div_rem(hz as u64, g).0 }
    }

    /// The frequency, in Hz.
    pub const fn hz(&self) -> u32 {
        self.hz
    }

    /// `ticks` in nanoseconds, rounded down (saturating at `u64::MAX`).
    pub const fn nanos(&self, ticks: u64) -> u64 {
        match ticks.checked_mul(self.num) {
            // `den` is at least 1 (see `from_hz`).
            Some(n) => div_rem(n, self.den).0,
            None => u64::MAX,
        }
    }

    /// `ticks` in microseconds, rounded down.
    pub const fn micros(&self, ticks: u64) -> u64 {
        div_rem(self.nanos(ticks), 1000).0
    }

    /// `ticks` as instructions retired under `-icount shift=0` (1 ns of
    /// virtual time per instruction): the same number as [`Self::nanos`].
    pub const fn instructions(&self, ticks: u64) -> u64 {
        self.nanos(ticks) >> ICOUNT_SHIFT
    }

    /// Instructions per tick, rounded up: a measured count is within this
    /// many instructions of the true one (plus the few instructions of the
    /// clock readings themselves).
    pub const fn resolution(&self) -> u64 {
        match div_rem(self.num, self.den) {
            (q, 0) => q,
            (q, _) => q.saturating_add(1),
        }
    }
}

/// QEMU's `-icount shift=N`: each instruction advances virtual time by
/// 2^N ns. The firmware is run with `shift=0`.
pub const ICOUNT_SHIFT: u32 = 0;

/// Iterations of the calibration loop (`calibrate`): 2 instructions each.
pub const CALIBRATION_ITERATIONS: u32 = 5_000_000;
/// Instructions the calibration loop retires.
pub const CALIBRATION_INSTRUCTIONS: u64 = 2 * CALIBRATION_ITERATIONS as u64;

/// What `calibrate` (on the firmware targets) found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Calibration {
    /// Instructions the loop measured (from ticks).
    pub measured: u64,
    /// Instructions the loop retires.
    pub expected: u64,
    /// Largest difference accepted.
    pub tolerance: u64,
}

impl Calibration {
    /// Whether the clock counted the loop's instructions, to within the
    /// tolerance: the timer's frequency is what the board says, and QEMU
    /// runs with `-icount shift=0`.
    pub const fn ok(&self) -> bool {
        self.measured.abs_diff(self.expected) <= self.tolerance
    }
}

/// The tolerance of a calibration with `clock`: two ticks (one at each
/// reading) and 200 instructions for the readings, the call and the loop's
/// set-up.
pub const fn calibration_tolerance(rate: TickRate) -> u64 {
    2 * rate.resolution() + 200
}

/// Times a loop of [`CALIBRATION_INSTRUCTIONS`] instructions (a
/// decrement-and-branch loop in assembly, 2 instructions per iteration) with
/// `clock`. Only on the firmware targets (Arm and RISC-V, bare metal).
#[cfg(all(target_os = "none", any(target_arch = "arm", target_arch = "riscv32")))]
pub fn calibrate<C: Clock>(clock: &mut C) -> Calibration {
    let rate = clock.rate();
    let ((), ticks) = measure(clock, || busy_loop(CALIBRATION_ITERATIONS));
    Calibration {
        measured: rate.instructions(ticks),
        expected: CALIBRATION_INSTRUCTIONS,
        tolerance: calibration_tolerance(rate),
    }
}

/// `n` iterations (at least 1) of a 2-instruction loop.
#[cfg(all(target_os = "none", target_arch = "arm"))]
#[inline(always)]
fn busy_loop(n: u32) {
    // SAFETY: only decrements a scratch register and branches; touches no
    // memory and no flags anyone reads afterwards.
    unsafe {
        core::arch::asm!(
            "2:",
            "subs {n}, #1",
            "bne 2b",
            n = inout(reg) n.max(1) => _,
            options(nomem, nostack),
        );
    }
}

/// `n` iterations (at least 1) of a 2-instruction loop.
#[cfg(all(target_os = "none", target_arch = "riscv32"))]
#[inline(always)]
fn busy_loop(n: u32) {
    // SAFETY: only decrements a scratch register and branches; touches no
    // memory.
    unsafe {
        core::arch::asm!(
            "2:",
            "addi {n}, {n}, -1",
            "bnez {n}, 2b",
            n = inout(reg) n.max(1) => _,
            options(nomem, nostack),
        );
    }
}

/// The Armv6-M/Armv7-M SysTick as a 64-bit [`Clock`]: the 24-bit down
/// counter runs from the processor clock with reload `0xFF_FFFF`, and the
/// SysTick exception counts its wraps. The board's SysTick exception
/// handler must call [`systick::on_wrap`].
#[cfg(all(target_os = "none", target_arch = "arm"))]
pub mod systick {
    use super::{Clock, TickRate};
    use core::ptr::{read_volatile, write_volatile};
    use core::sync::atomic::{AtomicU32, Ordering};

    /// SysTick Control and Status Register.
    const SYST_CSR: *mut u32 = 0xE000_E010 as *mut u32;
    /// SysTick Reload Value Register.
    const SYST_RVR: *mut u32 = 0xE000_E014 as *mut u32;
    /// SysTick Current Value Register.
    const SYST_CVR: *mut u32 = 0xE000_E018 as *mut u32;
    /// Interrupt Control and State Register (PENDSTSET is bit 26).
    const SCB_ICSR: *const u32 = 0xE000_ED04 as *const u32;
    const PENDSTSET: u32 = 1 << 26;
    /// CSR: ENABLE | TICKINT (exception on wrap) | CLKSOURCE (processor clock).
    const CSR_RUN: u32 = 0b111;

    /// The reload value: the largest the 24-bit counter holds, so the
    /// counter wraps every 2^24 ticks.
    pub const RELOAD: u32 = 0x00FF_FFFF;

    /// Wraps counted by [`on_wrap`] (written only by the SysTick exception,
    /// read with the exception masked).
    static WRAPS: AtomicU32 = AtomicU32::new(0);

    /// Counts one wrap; call from the SysTick exception handler, and from
    /// nowhere else.
    pub fn on_wrap() {
        // Only the exception writes WRAPS, so load + store is a whole
        // increment (Armv6-M has no atomic read-modify-write).
        WRAPS.store(WRAPS.load(Ordering::Relaxed).wrapping_add(1), Ordering::Relaxed);
    }

    /// The running SysTick.
    pub struct SysTick {
        rate: TickRate,
    }

    impl SysTick {
        /// Starts SysTick from the processor clock, which runs at `cpu_hz`
        /// (the frequency QEMU gives the machine's `cpuclk`).
        ///
        /// # Safety
        /// Takes SysTick over: nothing else may use it, and the SysTick
        /// exception handler must call [`on_wrap`].
        pub unsafe fn start(cpu_hz: u32) -> Self {
            // SAFETY: SysTick registers of the System Control Space, always
            // present on these cores (QEMU models one on every M-profile
            // machine); the caller owns SysTick.
            unsafe {
                write_volatile(SYST_CSR, 0);
                write_volatile(SYST_RVR, RELOAD);
                // Any write clears the current value (and COUNTFLAG).
                write_volatile(SYST_CVR, 0);
                WRAPS.store(0, Ordering::Relaxed);
                write_volatile(SYST_CSR, CSR_RUN);
                // The cleared counter reads 0 until its first tick loads
                // the reload value (without a wrap): wait for that, so that
                // the first period starts at RELOAD like every other one.
                // Bounded: a SysTick that never ticks fails the
                // calibration instead of hanging here.
                let mut spins = 0u32;
                while read_volatile(SYST_CVR) == 0 && spins < 1_000_000 {
                    spins += 1;
                }
            }
            SysTick { rate: TickRate::from_hz(cpu_hz) }
        }
    }

    impl Clock for SysTick {
        fn now(&mut self) -> u64 {
            cortex_m::interrupt::free(|_| {
                // With the exception masked, WRAPS cannot change; a wrap that
                // happened but is not yet counted shows as a pending SysTick.
                // SAFETY: reads of SysTick and SCB registers.
                let (wraps, value) = unsafe {
                    let wraps = WRAPS.load(Ordering::Relaxed) as u64;
                    let value = read_volatile(SYST_CVR);
                    if read_volatile(SCB_ICSR) & PENDSTSET != 0 {
                        // Wrapped before (or just after) that read: the
                        // value read again is in the new period.
                        (wraps + 1, read_volatile(SYST_CVR))
                    } else {
                        (wraps, value)
                    }
                };
                let period = RELOAD as u64 + 1;
                wraps * period + (RELOAD.saturating_sub(value & RELOAD)) as u64
            })
        }
        fn rate(&self) -> TickRate {
            self.rate
        }
    }
}

/// The RISC-V ACLINT/CLINT machine timer (`mtime`, 64 bits) of QEMU's `virt`
/// machine, at 10 MHz, as a [`Clock`].
#[cfg(all(target_os = "none", target_arch = "riscv32"))]
pub mod mtime {
    use super::{Clock, TickRate};
    use core::ptr::read_volatile;

    /// `mtime`, low word (CLINT base 0x0200_0000 + 0xBFF8).
    const MTIME_LO: *const u32 = 0x0200_BFF8 as *const u32;
    /// `mtime`, high word.
    const MTIME_HI: *const u32 = 0x0200_BFFC as *const u32;
    /// The frequency of QEMU `virt`'s `mtime` (its default timebase).
    pub const VIRT_MTIME_HZ: u32 = 10_000_000;

    /// QEMU `virt`'s `mtime`.
    pub struct Mtime;

    impl Clock for Mtime {
        fn now(&mut self) -> u64 {
            loop {
                // SAFETY: the CLINT's `mtime` registers, always mapped on
                // QEMU's `virt` machine; reading has no side effect.
                let (hi, lo, hi2) =
                    unsafe { (read_volatile(MTIME_HI), read_volatile(MTIME_LO), read_volatile(MTIME_HI)) };
                // A carry into the high word between the reads: read again.
                if hi == hi2 {
                    return ((hi as u64) << 32) | lo as u64;
                }
            }
        }
        fn rate(&self) -> TickRate {
            TickRate::from_hz(VIRT_MTIME_HZ)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A clock that advances by a set step at every reading.
    struct Steps {
        t: u64,
        step: u64,
        rate: TickRate,
    }
    impl Clock for Steps {
        fn now(&mut self) -> u64 {
            self.t += self.step;
            self.t
        }
        fn rate(&self) -> TickRate {
            self.rate
        }
    }

    #[test]
    fn long_division_matches_the_library() {
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = || {
            // SplitMix64.
            x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = x;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        };
        let edges = [1, 2, 3, 7, 10, 1000, 1 << 31, u32::MAX as u64, 1 << 63, (1 << 63) + 1, u64::MAX - 1, u64::MAX];
        for &n in edges.iter().chain(&[0, 5, 999, 1_000_000_000]) {
            for &d in &edges {
                assert_eq!(div_rem_u64(n, d), (n / d, n % d), "{n} / {d}");
            }
        }
        for _ in 0..100_000 {
            let (n, d) = (next(), next() >> (next() % 64));
            if d != 0 {
                assert_eq!(div_rem_u64(n, d), (n / d, n % d), "{n} / {d}");
            }
        }
        assert_eq!(div_rem_u64(7, 0), (u64::MAX, 7));
    }

    #[test]
    fn tick_rates_reduce_and_convert() {
        // mps2-an386's cpuclk: 25 MHz, 40 ns per tick.
        let r = TickRate::from_hz(25_000_000);
        assert_eq!((r.num, r.den, r.hz()), (40, 1, 25_000_000));
        assert_eq!(r.instructions(1_000), 40_000);
        assert_eq!(r.resolution(), 40);
        // microbit (nRF51) cpuclk: 16 MHz, 62.5 ns per tick.
        let r = TickRate::from_hz(16_000_000);
        assert_eq!((r.num, r.den), (125, 2));
        assert_eq!(r.instructions(3), 187); // 187.5, rounded down
        assert_eq!(r.instructions(16_000_000), 1_000_000_000);
        assert_eq!(r.resolution(), 63);
        // riscv virt mtime: 10 MHz, 100 ns per tick.
        let r = TickRate::from_hz(10_000_000);
        assert_eq!((r.instructions(7), r.resolution()), (700, 100));
        // RP2040 timer: 1 MHz, microseconds.
        let r = TickRate::from_hz(1_000_000);
        assert_eq!((r.micros(1_234_567), r.nanos(2)), (1_234_567, 2_000));
        // An odd frequency: 1e9 / 3 Hz is 3 ns per tick.
        assert_eq!(TickRate::from_hz(333_333_333).resolution(), 4);
    }

    #[test]
    fn conversions_never_overflow_or_divide_by_zero() {
        let r = TickRate::from_hz(0);
        assert_eq!(r.hz(), 1);
        assert_eq!(r.nanos(5), 5 * NANOS_PER_SECOND);
        assert_eq!(r.nanos(u64::MAX), u64::MAX);
        assert_eq!(TickRate::from_hz(16_000_000).instructions(u64::MAX), u64::MAX);
    }

    #[test]
    fn measure_returns_the_result_and_the_elapsed_ticks() {
        let mut c = Steps { t: 100, step: 7, rate: TickRate::from_hz(1_000_000) };
        let mut ran = false;
        let (v, ticks) = measure(&mut c, || {
            ran = true;
            42
        });
        assert!(ran);
        assert_eq!((v, ticks), (42, 7));
    }

    #[test]
    fn calibration_tolerance_covers_two_ticks() {
        let r = TickRate::from_hz(16_000_000);
        let t = calibration_tolerance(r);
        assert_eq!(t, 2 * 63 + 200);
        let c =
            Calibration { measured: CALIBRATION_INSTRUCTIONS + t, expected: CALIBRATION_INSTRUCTIONS, tolerance: t };
        assert!(c.ok());
        assert!(!Calibration { measured: CALIBRATION_INSTRUCTIONS / 2, ..c }.ok());
        // A clock running in real time instead of instructions (no -icount)
        // is far off.
        assert!(!Calibration { measured: 3 * CALIBRATION_INSTRUCTIONS, ..c }.ok());
    }
}
