//! What the front ends' tests share with the inner crates' tests: where
//! the sample data is (`FOGBANK_DATA_DIR`, `../shared/data`), the skip-or-
//! fail rule for optional tools (`FOGBANK_REQUIRE_*`), and the test GPU
//! (lavapipe in CI). Here so that a front end's tests, like the front end,
//! reach the inner crates through `fogbank` alone.

pub use fogbank_gpu::test_gpu;
pub use fogbank_math::{sample_data, testdata};
