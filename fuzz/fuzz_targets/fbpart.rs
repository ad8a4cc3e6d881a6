//! Any byte string must parse to a partial result or to an error — also
//! with a valid checksum appended, so the fuzzer gets past it into the
//! header and records — and a parsed partial must merge with itself (a
//! duplicate, refused) and alone, and round-trip through its bytes: no
//! panic, abort, hang or outsized allocation.
#![no_main]

use fogbank_partial::merge::merge;
use fogbank_partial::partial::{fnv1a, Partial};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = Partial::from_bytes(data);
    let mut sealed = data.to_vec();
    sealed.extend_from_slice(&fnv1a(data).to_le_bytes());
    if let Ok(p) = Partial::from_bytes(&sealed) {
        let again = Partial::from_bytes(&p.to_bytes()).expect("a written partial reads back");
        assert!(again.film.sums == p.film.sums && again.film.count == p.film.count);
        let one = [("a".to_string(), p)];
        let _ = merge(&one, true);
        let two = [one[0].clone(), ("b".to_string(), one[0].1.clone())];
        let _ = merge(&two, true);
    }
});
