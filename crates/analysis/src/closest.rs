//! The closest name (`diagnostics.md` §2.2) for "did you mean" quick fixes: smallest
//! case-insensitive Levenshtein distance, ties to the first candidate, offered only within
//! max(2, ⌊len/3⌋).

/// The closest candidate to `written`, if it is close enough.
pub fn closest<'a>(
    written: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Option<&'a str> {
    let written_upper = written.to_ascii_uppercase();
    let limit = 2.max(written.chars().count() / 3);
    let mut best: Option<(usize, &'a str)> = None;
    for candidate in candidates {
        let length_gap = candidate.chars().count().abs_diff(written.chars().count());
        if length_gap > limit {
            continue;
        }
        let distance = levenshtein(&written_upper, &candidate.to_ascii_uppercase());
        if distance <= limit && best.is_none_or(|(d, _)| distance < d) {
            best = Some((distance, candidate));
        }
    }
    best.map(|(_, c)| c)
}

/// Edit distance between two strings (by characters).
pub fn levenshtein(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut previous: Vec<usize> = (0..=b.len()).collect();
    let mut current = vec![0; b.len() + 1];
    for (i, ca) in a.chars().enumerate() {
        current[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let cost = usize::from(ca != cb);
            current[j + 1] = (previous[j] + cost)
                .min(previous[j + 1] + 1)
                .min(current[j] + 1);
        }
        std::mem::swap(&mut previous, &mut current);
    }
    previous[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_closest_name() {
        assert_eq!(closest("Obne", ["Oben", "Unten"]), Some("Oben"));
        assert_eq!(closest("xyz", ["Oben", "Unten"]), None);
        // Ties go to the first candidate.
        assert_eq!(closest("ab", ["aa", "bb"]), Some("aa"));
        assert_eq!(closest("OBEN", ["oben"]), Some("oben"));
        assert_eq!(levenshtein("kitten", "sitting"), 3);
    }
}
