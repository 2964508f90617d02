//! Random and mutated bytes through both readers: always a value or a typed error, never a panic.
//! (A panic fails the proptest; the MAT path also checks that `matfile` was never reached with
//! input that would make it panic, since our validator runs first.)

mod common;

use bearing_data::{
    Column, CsvOptions, parse_record, read_csv, read_mat_tree, read_variable_sets, select_signal,
    validate_structure,
};
use proptest::prelude::*;
use std::sync::Once;
use std::sync::atomic::{AtomicBool, Ordering};

static PANICKED: AtomicBool = AtomicBool::new(false);
static HOOK: Once = Once::new();

/// Record any panic, even one caught by the reader's last-resort `catch_unwind`, so these tests
/// prove the structural validator keeps `matfile` from panicking at all.
fn watch_panics() {
    HOOK.call_once(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            PANICKED.store(true, Ordering::SeqCst);
            default(info);
        }));
    });
}

fn header() -> Vec<u8> {
    common::tiny_cwru(105, 1797)[..128].to_vec()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn random_bytes_never_panic_the_mat_reader(body in prop::collection::vec(any::<u8>(), 0..600)) {
        watch_panics();
        let _ = parse_record(&body, 105);
        let mut b = header();
        b.extend_from_slice(&body);
        let _ = validate_structure(&b);
        let _ = read_variable_sets(&b);
        let _ = parse_record(&b, 105);
        prop_assert!(!PANICKED.load(Ordering::SeqCst));
    }

    #[test]
    fn mutated_mat_files_never_panic(
        edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..8),
        cut in any::<prop::sample::Index>(),
    ) {
        let mut b = common::tiny_cwru(105, 1797);
        for (i, v) in &edits {
            let k = i.index(b.len());
            b[k] = *v;
        }
        let _ = parse_record(&b, 105);
        let keep = cut.index(b.len() + 1);
        watch_panics();
        let _ = parse_record(&b[..keep], 105);
        prop_assert!(!PANICKED.load(Ordering::SeqCst));
    }

    #[test]
    fn mutated_tag_words_never_panic(
        pos in 0usize..40,
        word in prop_oneof![Just(u32::MAX), Just(u32::MAX - 7), Just(0x7FFF_FFFF), Just(0x0004_0004), any::<u32>()],
    ) {
        // Overwrite one 4-byte word of the first element (tags, lengths, flags, dims) with
        // values chosen to hit overflow paths.
        let mut b = common::tiny_cwru(105, 1797);
        let at = 128 + 4 * pos;
        b[at..at + 4].copy_from_slice(&word.to_le_bytes());
        watch_panics();
        let _ = parse_record(&b, 105);
        prop_assert!(!PANICKED.load(Ordering::SeqCst));
    }

    #[test]
    fn mutated_mat_trees_never_panic_the_generic_reader(
        which in 0usize..3,
        edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..8),
        word in prop_oneof![Just(u32::MAX), Just(0x7FFF_FFFF), Just(0x0004_0004), Just(0), any::<u32>()],
        at in any::<prop::sample::Index>(),
        cut in any::<prop::sample::Index>(),
    ) {
        let name = ["struct_v5.mat", "plain.mat", "mfpt_like.mat"][which];
        let mut b = common::mat_fixtures::fixture(name);
        for (i, v) in &edits {
            let k = 128 + i.index(b.len() - 128);
            b[k] = *v;
        }
        let k = 128 + at.index(b.len() - 132) / 4 * 4;
        b[k..k + 4].copy_from_slice(&word.to_le_bytes());
        let keep = cut.index(b.len() + 1);
        watch_panics();
        for bytes in [&b[..], &b[..keep]] {
            if let Ok(leaves) = read_mat_tree(bytes) {
                let _ = select_signal(&leaves, None);
                let _ = select_signal(&leaves, Some("Data"));
            }
        }
        prop_assert!(!PANICKED.load(Ordering::SeqCst));
    }

    #[test]
    fn random_text_never_panics_the_csv_reader(
        text in prop::collection::vec(prop_oneof![Just(b'1'), Just(b','), Just(b'\n'), Just(b'"'), Just(b'#'),
            Just(b'.'), Just(b'e'), Just(b'-'), Just(b'N'), any::<u8>()], 0..200),
        col in 0usize..3,
    ) {
        for column in [Column::Single, Column::Index(col), Column::Name("accel".into())] {
            let _ = read_csv(text.as_slice(), &CsvOptions::new(1_000.0, column));
        }
    }
}
