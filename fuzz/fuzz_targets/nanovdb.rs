//! Any byte string must parse to a grid or to an error: no panic, abort,
//! hang or outsized allocation.
#![no_main]

use std::path::Path;

use fogbank_volume::loaders::nanovdb;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let path = Path::new("fuzz.nvdb");
    let _ = nanovdb::list_grids_from_bytes(path, data);
    if let Ok(grid) = nanovdb::read_grid_from_bytes(path, data, None) {
        // The statistics walk every leaf and tile; they must cope with
        // whatever a corrupted tree holds.
        let _ = grid.active_voxel_count();
        let _ = grid.active_bbox();
        let _ = grid.active_value_range();
        let _ = grid.active_value_sum();
        let _ = grid.value_at([0, 0, 0]);
    }
    if let Ok(grids) = nanovdb::read_vec3_grid_from_bytes(path, data, None) {
        for grid in &grids {
            let _ = grid.active_voxel_count();
            let _ = grid.active_bbox();
            let _ = grid.active_value_sum();
        }
    }
});
