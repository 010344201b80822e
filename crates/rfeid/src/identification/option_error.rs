//! An option refused, in words that belong to no front end: the option is
//! named as the reference names it (`plan`, `over_box`), and each front end
//! spells it its own way ([`Spelling`]): the command line `--over-box 0: …`,
//! the Python module `over_box=0: …`.

/// Every option a front end may be told about, as the reference names
/// them: those of the search ([`super::options::SearchOptions`]), the
/// model's settings for one run (`set`, `tolerance`, `substeps`), the
/// simulated record's noise, the design's request and the data to check.
/// An option named in backticks inside a message (`` `choose` ``) is
/// respelt by [`OptionError::spelt`].
pub const OPTION_NAMES: [&str; 20] = [
    "plan",
    "starts",
    "method",
    "weights",
    "noise_model",
    "threads",
    "from",
    "window",
    "start",
    "jacobian_memory",
    "profile_points",
    "set",
    "tolerance",
    "substeps",
    "noise",
    "noise_corner",
    "choose",
    "over_box",
    "data",
    "experiment",
];

/// An option outside its range, or options that do not go together: the
/// option's name (snake case, one of [`OPTION_NAMES`]) and what is wrong
/// with its value. Its own words name the option in backticks
/// (`` `plan` 0: must be … ``), as they name any other option the detail
/// mentions (`` `over_box` without `choose` ``).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("`{option}`{}{detail}", separator(detail, " "))]
pub struct OptionError {
    /// The option (`plan`, `starts`, …).
    pub option: &'static str,
    /// Its value and what is wrong with it (`0: must be 1 to 1000000`), or
    /// what is wrong when no value was given.
    pub detail: String,
}

/// How a front end spells an option's name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Spelling {
    /// A command-line flag: `--over-box 4`.
    CommandLine,
    /// A Python keyword argument: `over_box=4` (`from` is `from_`).
    Keyword,
}

impl Spelling {
    /// `option` (snake case) as this front end writes it.
    pub fn name(self, option: &str) -> String {
        match (self, option) {
            (Spelling::CommandLine, o) => format!("--{}", o.replace('_', "-")),
            (Spelling::Keyword, "from") => "from_".to_string(),
            (Spelling::Keyword, o) => o.to_string(),
        }
    }

    /// What joins an option's name and its value.
    fn joiner(self) -> &'static str {
        match self {
            Spelling::CommandLine => " ",
            Spelling::Keyword => "=",
        }
    }
}

impl OptionError {
    pub(crate) fn new(option: &'static str, detail: String) -> Self {
        OptionError { option, detail }
    }

    /// The message as the front end `spelling` writes it: the option's
    /// name, joined to the detail ([`Spelling::joiner`] when the detail
    /// starts with the value), and every option the detail names in
    /// backticks spelt the same way.
    pub fn spelt(&self, spelling: Spelling) -> String {
        let detail = respelt(&self.detail, spelling);
        let joiner = separator(&detail, spelling.joiner());
        format!("{}{joiner}{detail}", spelling.name(self.option))
    }
}

/// What follows an option's name before `detail`: nothing before a colon,
/// `joiner` before a value, else a space.
fn separator(detail: &str, joiner: &'static str) -> &'static str {
    if detail.starts_with(':') {
        ""
    } else if is_value(detail) {
        joiner
    } else {
        " "
    }
}

/// `text` with each option of [`OPTION_NAMES`] named in backticks spelt
/// by `spelling`; other backticked words are left as they are.
fn respelt(text: &str, spelling: Spelling) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(open) = rest.find('`') {
        let after = &rest[open + 1..];
        let Some(close) = after.find('`') else { break };
        let word = &after[..close];
        out.push_str(&rest[..open]);
        match OPTION_NAMES.contains(&word) {
            true => out.push_str(&spelling.name(word)),
            false => out.push_str(&rest[open..open + close + 2]),
        }
        rest = &after[close + 1..];
    }
    out.push_str(rest);
    out
}

/// Whether `text` starts with a value (what follows an option's name when
/// it is the option's value): a number or a quoted word.
fn is_value(text: &str) -> bool {
    text.starts_with(|c: char| c.is_ascii_digit() || "+-.'".contains(c))
        || ["inf", "nan", "NaN"].iter().any(|w| text.starts_with(w))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn e(option: &'static str, detail: &str) -> OptionError {
        OptionError::new(option, detail.to_string())
    }

    #[test]
    fn each_front_end_spells_the_options_its_own_way() {
        let cases = [
            (
                e("plan", "0: must be 1 to 9"),
                "`plan` 0: must be 1 to 9",
                "--plan 0: must be 1 to 9",
                "plan=0: must be 1 to 9",
            ),
            (
                e("from", "9: must lie in [0, 1) s"),
                "`from` 9: must lie in [0, 1) s",
                "--from 9: must lie in [0, 1) s",
                "from_=9: must lie in [0, 1) s",
            ),
            (
                e("over_box", "without `choose`: give `choose` too"),
                "`over_box` without `choose`: give `choose` too",
                "--over-box without --choose: give --choose too",
                "over_box without choose: give choose too",
            ),
            (
                e("set", ": unknown parameter 'q'"),
                "`set`: unknown parameter 'q'",
                "--set: unknown parameter 'q'",
                "set: unknown parameter 'q'",
            ),
            (
                e("method", "'x': must be one of lm, bfgs"),
                "`method` 'x': must be one of lm, bfgs",
                "--method 'x': must be one of lm, bfgs",
                "method='x': must be one of lm, bfgs",
            ),
            (
                e("noise", "-1: must be a fraction (`set = { … }` stays)"),
                "`noise` -1: must be a fraction (`set = { … }` stays)",
                "--noise -1: must be a fraction (`set = { … }` stays)",
                "noise=-1: must be a fraction (`set = { … }` stays)",
            ),
        ];
        for (error, neutral, cli, keyword) in cases {
            assert_eq!(error.to_string(), neutral);
            assert_eq!(error.spelt(Spelling::CommandLine), cli);
            assert_eq!(error.spelt(Spelling::Keyword), keyword);
        }
    }

    #[test]
    fn an_unclosed_backtick_is_kept() {
        let error = e("set", "'a`b': expected NAME=VALUE");
        assert_eq!(
            error.spelt(Spelling::CommandLine),
            "--set 'a`b': expected NAME=VALUE"
        );
    }
}
