//! Smith & Randall's diagnosability grades of the 60 12 kHz drive-end CWRU records (MSSP 64–65,
//! 2015; the table in `shared/docs/references.md`): `Y` clearly diagnosable by envelope
//! analysis, `P` partly, `N` not. Embedded as data (44 Y, 6 P, 10 N); records the paper does
//! not grade (97, the 48 kHz records) have none.

use std::collections::BTreeMap;
use std::sync::OnceLock;

const GRADES_CSV: &str = include_str!("smith_randall_grades.csv");

/// Smith & Randall's grade of CWRU record `number` (`'Y'`, `'P'` or `'N'`), if it has one.
pub fn smith_randall_grade(number: u32) -> Option<char> {
    static GRADES: OnceLock<BTreeMap<u32, char>> = OnceLock::new();
    GRADES
        .get_or_init(|| {
            GRADES_CSV
                .lines()
                .filter(|l| !l.starts_with('#') && !l.starts_with("record"))
                .filter_map(|l| {
                    let f: Vec<&str> = l.trim().split(',').collect();
                    Some((f.first()?.parse().ok()?, f.last()?.chars().next()?))
                })
                .collect()
        })
        .get(&number)
        .copied()
}

#[cfg(test)]
mod tests {
    use super::smith_randall_grade;

    #[test]
    fn grades_count_as_published() {
        let all: Vec<char> = (0..4000).filter_map(smith_randall_grade).collect();
        assert_eq!(all.len(), 60);
        for (g, n) in [('Y', 44), ('P', 6), ('N', 10)] {
            assert_eq!(all.iter().filter(|&&c| c == g).count(), n, "grade {g}");
        }
        assert_eq!(smith_randall_grade(105), Some('Y'));
        assert_eq!(smith_randall_grade(200), Some('N'));
        assert_eq!(smith_randall_grade(97), None);
    }
}
