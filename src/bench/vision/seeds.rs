//! The seeds `--seed` names: one, a list, a range, or a mix.

/// The seeds named, in the order given, each once.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Seeds(pub Vec<u64>);

/// Reads `1`, `1,4,7`, `12-21` or a mix.
pub fn parse_seeds(text: &str) -> Result<Seeds, String> {
    let mut seeds: Vec<u64> = Vec::new();
    for part in text.split(',').map(str::trim) {
        let number = |s: &str| {
            s.trim().parse::<u64>().map_err(|_| {
                format!("'{s}' in '{text}': expected a seed (a whole number), a list 1,4,7 or a range 12-21")
            })
        };
        let (first, last) = match part.split_once('-') {
            Some((a, b)) => (number(a)?, number(b)?),
            None => {
                let n = number(part)?;
                (n, n)
            }
        };
        if first > last {
            return Err(format!("range '{part}' in '{text}' runs backwards"));
        }
        if last - first >= 10_000 {
            return Err(format!(
                "range '{part}' in '{text}' names more than 10 000 seeds"
            ));
        }
        for seed in first..=last {
            if !seeds.contains(&seed) {
                seeds.push(seed);
            }
        }
    }
    Ok(Seeds(seeds))
}

#[cfg(test)]
mod tests {
    use super::parse_seeds;

    #[test]
    fn seeds_are_read_as_lists_and_ranges_each_once() {
        assert_eq!(parse_seeds("1").unwrap().0, [1]);
        assert_eq!(parse_seeds("12-14, 3,13").unwrap().0, [12, 13, 14, 3]);
        let backwards = parse_seeds("5-3").unwrap_err();
        assert!(backwards.contains("'5-3'"), "{backwards}");
        let word = parse_seeds("1,x").unwrap_err();
        assert!(word.contains("'x'") && word.contains("'1,x'"), "{word}");
    }
}
