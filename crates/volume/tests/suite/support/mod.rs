//! Shared by the loader robustness tests: a counting allocator that
//! records the largest single allocation, a way to run a test in a process
//! of its own, and a deterministic xorshift.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

pub struct Counting;

/// The suite's allocator; only the tests run by [`in_own_process`] read it.
#[global_allocator]
static GLOBAL: Counting = Counting;

pub static LARGEST: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        System.alloc(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        System.alloc_zeroed(layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        LARGEST.fetch_max(new_size, Ordering::Relaxed);
        System.realloc(ptr, layout, new_size)
    }
}

/// The largest single allocation so far.
pub fn largest() -> usize {
    LARGEST.load(Ordering::Relaxed)
}

/// Runs `body` in a process of its own: this test binary run again with
/// only the calling test. [`largest`] is the process's largest allocation,
/// and the suite's other tests, running in parallel threads of the same
/// process, would count against the calling test's limit.
pub fn in_own_process(body: impl FnOnce()) {
    const VAR: &str = "FOGBANK_TEST_OWN_PROCESS";
    let thread = std::thread::current();
    // The test harness names each test's thread after the test.
    let test = match thread.name() {
        Some(name) if name != "main" && std::env::var_os(VAR).is_none() => name,
        _ => return body(),
    };
    let exe = std::env::current_exe().expect("the test binary's path");
    let out = std::process::Command::new(exe)
        .args(["--exact", test, "--test-threads=1", "--nocapture"])
        .env(VAR, "1")
        .output()
        .expect("running the test binary again");
    let text = String::from_utf8_lossy(&out.stdout) + String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success() && text.contains("1 passed"),
        "{test} in a process of its own:\n{text}"
    );
}

/// Deterministic xorshift so that failures reproduce.
pub struct Rng(pub u64);
impl Rng {
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
}

/// A panic's message, if `f` panicked.
pub fn panic_message(f: impl FnOnce()) -> Option<String> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f))
        .err()
        .map(|e| {
            e.downcast_ref::<String>()
                .cloned()
                .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default()
        })
}
