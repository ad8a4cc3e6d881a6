//! In-memory voxel arrays a scene names as a field's source
//! (`density = { array = "array:3" }`): the way a numpy array from Python
//! (or a grid a program computed) enters a scene without a file.
//!
//! The registry holds arrays weakly: an array lives as long as its owner
//! (the Python `Grid`, which scenes using it keep alive) and a scene built
//! after it is gone gets an error naming it, never a dangling read. Names
//! are never reused within a process.

use crate::error::SceneError;
use fogbank_volume::VoxelArray;
use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, Weak};

static NEXT: AtomicU64 = AtomicU64::new(1);
static ARRAYS: Mutex<Option<HashMap<String, Weak<dyn VoxelArray>>>> = Mutex::new(None);

/// Registers `array` and returns the name scenes give it.
pub fn register(array: &Arc<dyn VoxelArray>) -> String {
    let name = format!("array:{}", NEXT.fetch_add(1, Ordering::Relaxed));
    let mut table = ARRAYS.lock().unwrap_or_else(|e| e.into_inner());
    let table = table.get_or_insert_with(HashMap::new);
    // Forget arrays whose owners are gone, so the table stays small.
    table.retain(|_, a| a.strong_count() > 0);
    table.insert(name.clone(), Arc::downgrade(array));
    name
}

/// The array `name` of scene key `key`.
pub fn get(name: &str, key: &str) -> Result<Arc<dyn VoxelArray>, SceneError> {
    let table = ARRAYS.lock().unwrap_or_else(|e| e.into_inner());
    table
        .as_ref()
        .and_then(|t| t.get(name))
        .and_then(Weak::upgrade)
        .ok_or_else(|| {
            SceneError(format!(
                "{key}.array: no array `{name}` in this process (arrays are registered by the program that holds them, e.g. fogbank.Grid in Python, and exist while it keeps them)"
            ))
        })
}

#[cfg(test)]
mod arrays_test {
    use super::*;
    use fogbank_volume::DenseArray;

    #[test]
    fn an_array_is_found_while_its_owner_keeps_it() {
        let a: Arc<dyn VoxelArray> = Arc::new(
            DenseArray::new(
                [1, 1, 1],
                1,
                vec![2.0],
                fogbank_math::DAffine3::IDENTITY,
                "t".into(),
            )
            .unwrap(),
        );
        let name = register(&a);
        assert_eq!(
            get(&name, "media.0.density").unwrap().value(0, 0, 0, 0),
            2.0
        );
        drop(a);
        let e = get(&name, "media.0.density").unwrap_err().0;
        assert!(
            e.contains("media.0.density.array") && e.contains(&name),
            "{e}"
        );
    }
}
