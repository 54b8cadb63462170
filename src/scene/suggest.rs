//! "Did you mean": the defined names closest to a misspelt one, for an error message that
//! stays one short line however many names the scene defines.

use crate::input::quote;

/// How many names a message lists.
const SHOWN: usize = 3;
/// Names are compared on their first 32 characters, which bounds the cost per name.
const PREFIX: usize = 32;

/// Levenshtein distance between `a` and `b` (insertions, deletions, substitutions), one row
/// at a time.
fn distance(a: &[char], b: &[char]) -> usize {
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.iter().enumerate() {
        let mut diag = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let next = (diag + usize::from(ca != cb))
                .min(row[j] + 1)
                .min(row[j + 1] + 1);
            diag = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}

/// `"a", "b", "c" and 7 more` (closest to `wanted` first), or `none` for no names.
#[must_use]
pub(super) fn closest<'a>(wanted: &str, names: impl ExactSizeIterator<Item = &'a str>) -> String {
    let total = names.len();
    if total == 0 {
        return "none".into();
    }
    let w: Vec<char> = wanted.chars().take(PREFIX).collect();
    let mut best: Vec<(usize, &str)> = Vec::with_capacity(SHOWN + 1);
    for n in names {
        let c: Vec<char> = n.chars().take(PREFIX).collect();
        let d = distance(&w, &c);
        if best.len() < SHOWN || (d, n) < best[best.len() - 1] {
            let at = best.partition_point(|x| *x <= (d, n));
            best.insert(at, (d, n));
            best.truncate(SHOWN);
        }
    }
    let listed: Vec<String> = best.iter().map(|(_, n)| quote(n)).collect();
    let mut s = listed.join(", ");
    if total > best.len() {
        s.push_str(&format!(" and {} more", total - best.len()));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chars(s: &str) -> Vec<char> {
        s.chars().collect()
    }

    #[test]
    fn distances() {
        assert_eq!(distance(&chars("glass"), &chars("glass")), 0);
        assert_eq!(distance(&chars("glas"), &chars("glass")), 1);
        assert_eq!(distance(&chars("kitten"), &chars("sitting")), 3);
        assert_eq!(distance(&chars(""), &chars("abc")), 3);
    }

    #[test]
    fn closest_first_and_the_rest_counted() {
        let names = ["mirror", "glass", "floor", "glossy", "chalk"];
        assert_eq!(
            closest("glas", names.into_iter()),
            r#""glass", "glossy", "chalk" and 2 more"#
        );
        assert_eq!(closest("x", ["a"].into_iter()), r#""a""#);
        assert_eq!(closest("x", std::iter::empty()), "none");
        let many: Vec<String> = (0..100_000).map(|i| format!("m{i}")).collect();
        let s = closest("m77", many.iter().map(String::as_str));
        assert!(
            s.starts_with(r#""m77""#) && s.ends_with("and 99997 more"),
            "{s}"
        );
    }
}
