//! A table's recordings, protocols and labels, read from the transcription.

use pipeline::Protocol;
use pipeline::cells::Scope;
use pipeline::dissertation::chapter_tables;
use pipeline::recordings::RecKey;

fn full() -> Scope {
    Scope {
        loads: vec![0, 1, 2, 3],
        rpms: vec![300, 400, 450, 500],
    }
}

#[test]
fn fixed_load_table_needs_one_normal_and_every_fault_size() {
    let t = chapter_tables(2);
    let d = t.iter().find(|d| d.id == "2.3").expect("table 2.3");
    assert!(d.is_cwru() && !d.pooled());
    let keys = d.recording_keys(&full());
    // 97 serves every size; ball, outer, inner at three sizes each
    assert_eq!(keys.len(), 1 + 3 * 3);
    assert_eq!(keys.iter().filter(|k| k.class_index() == 0).count(), 1);
    assert_eq!(
        d.protocols(),
        vec![
            Protocol::RandomWindows,
            Protocol::TimeBlocked,
            Protocol::LeaveOneFaultSizeOut,
            Protocol::LeaveOneLoadOut
        ]
    );
    assert_eq!(d.crack_mils(2).expect("0.021 in"), 21);
}

#[test]
fn speed_variant_substitute_pools_four_speeds() {
    let t = chapter_tables(4);
    let d = t.iter().find(|d| d.id == "4.11").expect("table 4.11");
    assert!(!d.is_cwru() && d.pooled());
    assert_eq!(d.conditions(&full()), vec![300, 400, 450, 500]);
    // one normal per speed, seven fault classes at two sizes per speed
    assert_eq!(d.recording_keys(&full()).len(), 4 * (1 + 7 * 2));
    assert_eq!(d.condition_protocol(), Protocol::LeaveOneSpeedOut);
    assert_eq!(d.crack_mils(1).expect("6 mm"), 236);
    let labels: Vec<String> = d
        .recording_keys(&full())
        .iter()
        .map(RecKey::class_label)
        .collect();
    assert!(labels.contains(&"IR-OR-Ball".to_string()));
    // a table outside the scope is not run
    let quick = Scope {
        loads: vec![0],
        rpms: vec![300],
    };
    assert!(!d.selected(&quick));
}
