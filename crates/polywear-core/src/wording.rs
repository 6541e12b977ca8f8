//! Numbers and names written for people: plain numbers without float noise or needless
//! exponents (16.2, 0.005, 600 rather than 1.6226e1 or 599.9999999999999), and the closest
//! accepted name to a misspelt one ("did you mean `speed_kmh`?").

/// `x` rounded to `significant` digits, written without an exponent between 1e-5 and 1e10 and
/// with trailing zeros trimmed; outside that, as `1.5e-7`.
pub fn plain(x: f64, significant: usize) -> String {
    if !x.is_finite() {
        return x.to_string();
    }
    if x == 0.0 {
        return "0".into();
    }
    let sig = significant.clamp(1, 17);
    let sci = format!("{:.*e}", sig - 1, x);
    let (mantissa, exp) = sci.split_once('e').expect("exponent form");
    let exp: i32 = exp.parse().expect("exponent");
    if !(-5..10).contains(&exp) {
        return format!("{}e{exp}", trim_zeros(mantissa));
    }
    let decimals = (sig as i32 - 1 - exp).max(0) as usize;
    let rounded: f64 = sci.parse().expect("a number");
    trim_zeros(&format!("{rounded:.decimals$}"))
}

/// `x` in a data file (CSV, TOML): the shortest digits that read back to the same double, in
/// exponent form outside \[1e-5, 1e16) (`1e300`, never 301 digits), `NaN`, `inf` and `-inf`
/// spelled so. Every CSV polywear writes takes its numbers from here; people's words take
/// theirs from [`plain`].
pub fn data_number(x: f64) -> String {
    if x.is_nan() {
        return "NaN".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf" } else { "-inf" }.into();
    }
    let a = x.abs();
    if a != 0.0 && !(1e-5..1e16).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

fn trim_zeros(s: &str) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s.to_string()
    }
}

/// What a message may quote of a file's or a value's content: at most 16 characters, escaped
/// (line breaks, control characters and quotes written as `\n`, `\u{1}`, `\"`), in backticks,
/// with `…` when cut. A file refused for what it holds (a password file given as a CSV) is then
/// named, never shown.
pub fn snippet(s: &str) -> String {
    const MAX_CHARS: usize = 16;
    let cut = s.chars().count() > MAX_CHARS;
    let head: String = s.chars().take(MAX_CHARS).collect();
    let escaped: String = head.escape_debug().collect();
    format!("`{escaped}{}`", if cut { "…" } else { "" })
}

/// Text from a file (a band's `method`) as one line of at most `max_chars` characters:
/// control characters (line breaks among them) written escaped (`\n`), the rest cut with `…`,
/// so that no file can add lines, headings or pages to a summary or a report.
pub fn one_line(text: &str, max_chars: usize) -> String {
    let cut = text.chars().count() > max_chars;
    let mut out: String = text
        .chars()
        .take(max_chars)
        .flat_map(|c| {
            let escaped: Vec<char> = if c.is_control() {
                c.escape_debug().collect()
            } else {
                vec![c]
            };
            escaped
        })
        .collect();
    if cut {
        out.push('…');
    }
    out
}

/// `text` for Markdown: `&`, `<` and `>` as entities, so that a quoted text cannot open HTML.
pub fn markdown_text(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// The candidate closest to `typed` by edit distance (Levenshtein with a swap of two neighbouring
/// letters as one edit, the commonest typing slip: `waer` for `wear`), if it is close enough to
/// be a likely misspelling: at most a third of the name's letters changed (one in a name of three
/// or four letters, two or more in a longer one, none in a shorter one), or
/// `typed` a prefix of it (`speed` for `speed_kmh`), or it a prefix of `typed`, or `typed` its
/// last word of four letters or more (`patch` for `whole_patch`). Case is ignored.
pub fn closest<'a>(typed: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let t = typed.trim().to_lowercase();
    if t.is_empty() {
        return None;
    }
    let limit = match t.chars().count() {
        0..=2 => 0,
        3..=4 => 1,
        n => (n / 3).max(2),
    };
    candidates
        .into_iter()
        .filter_map(|c| {
            let lc = c.to_lowercase();
            let d = strsim::osa_distance(&t, &lc);
            let prefix = t.len() >= 3 && (lc.starts_with(&t) || t.starts_with(&lc));
            let last_word = t.len() >= 4 && lc.ends_with(&format!("_{t}"));
            (d <= limit || prefix || last_word).then_some((d, c))
        })
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c)
}

/// " did you mean `x`?" (with a leading space) for the closest candidate, or nothing.
pub fn did_you_mean<'a>(typed: &str, candidates: impl IntoIterator<Item = &'a str>) -> String {
    closest(typed, candidates)
        .map(|c| format!(" did you mean `{c}`?"))
        .unwrap_or_default()
}

/// `text` with its first letter in upper case, for a sentence that begins with a generated
/// phrase.
pub fn capitalise(text: &str) -> String {
    let mut c = text.chars();
    c.next()
        .map(|f| f.to_uppercase().chain(c).collect())
        .unwrap_or_default()
}

/// A whole number with thousands separators, rounded: 40,000. Negative numbers keep their sign.
pub fn thousands(x: f64) -> String {
    let digits = format!("{}", x.round().abs() as u64);
    let mut out = String::from(if x.round() < 0.0 { "-" } else { "" });
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// A distance in km with thousands separators: "40,000 km" (a fraction keeps its digits:
/// "2.5 km").
pub fn km(x: f64) -> String {
    if (x - x.round()).abs() > 1e-9 {
        return format!("{} km", plain(x, 9));
    }
    format!("{} km", thousands(x))
}

/// Seconds written as people read them: `42 s`, `3 min 20 s`, `2 h 05 min` (a run's elapsed
/// time or ETA in a progress line).
pub fn duration_text(secs: f64) -> String {
    let s = secs.max(0.0).round() as u64;
    match s {
        0..60 => format!("{s} s"),
        60..3600 => format!("{} min {:02} s", s / 60, s % 60),
        _ => format!("{} h {:02} min", s / 3600, (s % 3600) / 60),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations_read_as_seconds_minutes_or_hours() {
        assert_eq!(duration_text(42.4), "42 s");
        assert_eq!(duration_text(200.0), "3 min 20 s");
        assert_eq!(duration_text(7500.0), "2 h 05 min");
    }

    #[test]
    fn a_data_number_reads_back_exactly_and_never_runs_to_hundreds_of_digits() {
        for x in [
            0.0,
            1.0,
            -2.5,
            0.1,
            0.22999999999999998,
            1e300,
            -1e-300,
            1e16,
            9.999e15,
            1e-5,
            9.99e-6,
            123456.789,
            f64::MAX,
            f64::MIN_POSITIVE,
            5e-324,
        ] {
            let t = data_number(x);
            assert_eq!(t.parse::<f64>().unwrap().to_bits(), x.to_bits(), "{x}: {t}");
            assert!(t.len() <= 24, "{x}: {t}");
        }
        assert_eq!(data_number(1e300), "1e300");
        assert_eq!(data_number(4000.0), "4000");
        assert_eq!(
            (data_number(f64::NAN), data_number(f64::NEG_INFINITY)),
            ("NaN".to_string(), "-inf".to_string())
        );
    }

    #[test]
    fn a_file_s_text_is_quoted_as_one_bounded_line() {
        assert_eq!(one_line("a\n# b\u{7}", 40), "a\\n# b\\u{7}");
        assert_eq!(one_line(&"x".repeat(10), 4), "xxxx…");
        assert_eq!(markdown_text("a <b> & c"), "a &lt;b&gt; &amp; c");
    }

    #[test]
    fn distances_read_with_thousands_separators() {
        assert_eq!(km(40_000.0), "40,000 km");
        assert_eq!(km(1_000_000.0), "1,000,000 km");
        assert_eq!(km(999.0), "999 km");
        assert_eq!(km(2.5), "2.5 km");
    }

    #[test]
    fn snippets_are_short_and_escaped() {
        assert_eq!(snippet("speed_kmh"), "`speed_kmh`");
        assert_eq!(
            snippet("root:$6$saltsalt$hashhashhash:19000:0:99999:7:::\nbin:x"),
            "`root:$6$saltsalt…`"
        );
        assert_eq!(snippet("a\nb\"c"), "`a\\nb\\\"c`");
    }

    #[test]
    fn plain_numbers() {
        assert_eq!(plain(599.999_999_999_999_9, 6), "600");
        assert_eq!(plain(16.2261, 3), "16.2");
        assert_eq!(plain(0.005, 3), "0.005");
        assert_eq!(plain(-0.3, 6), "-0.3");
        assert_eq!(plain(200000.0, 3), "200000");
        assert_eq!(plain(7.365e-5, 3), "0.0000737");
        assert_eq!(plain(1.5e-7, 3), "1.5e-7");
        assert_eq!(plain(0.0, 3), "0");
    }

    #[test]
    fn closest_names() {
        let names = [
            "speed_kmh",
            "toe_deg",
            "load_n",
            "pressure_kpa",
            "g_mod",
            "mu_s",
            "mu_m",
        ];
        assert_eq!(closest("sped_kmh", names), Some("speed_kmh"));
        assert_eq!(closest("spede_kmh", names), Some("speed_kmh"));
        assert_eq!(closest("speed", names), Some("speed_kmh"));
        assert_eq!(closest("gmod", names), Some("g_mod"));
        assert_eq!(closest("Toe_Deg", names), Some("toe_deg"));
        assert_eq!(closest("wheelbase", names), None);
        // A swap of two neighbouring letters is one slip.
        assert_eq!(closest("waer", ["wear", "vibration"]), Some("wear"));
        // The last word of a name.
        assert_eq!(
            closest("patch", ["trailing", "whole_patch", "leading"]),
            Some("whole_patch")
        );
        assert_eq!(closest("kmh", names), None);
        assert_eq!(did_you_mean("xyz", names), "");
    }
}
