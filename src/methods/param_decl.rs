//! One typed declaration per method parameter: its key, its default, its range (or choices) and
//! its help, read by both the method's parser (`N.get(p, "regular")?`) and the listing
//! (`N.param()`, what `penumbra methods` prints and labels compare against).
//!
//! The default is written once, as the text the listing shows; the parser reads that same text
//! when the key is absent, so the listed default and the parsed one cannot differ (a default that
//! does not parse, or lies outside its range, fails the unit test over every declaration).

use super::{check_range, Param, ParamMap};
use crate::{Error, Result};

/// A value a parameter holds, parsed from its text with the message every method gives.
pub trait ParamValue: Copy + PartialOrd + std::fmt::Display {
    fn parse_param(key: &str, text: &str) -> Result<Self>;
}

impl ParamValue for u32 {
    fn parse_param(key: &str, v: &str) -> Result<u32> {
        v.parse().map_err(|_| {
            Error::Param(format!(
                "parameter {key} = `{v}` is not a non-negative integer"
            ))
        })
    }
}

impl ParamValue for f32 {
    fn parse_param(key: &str, v: &str) -> Result<f32> {
        match v.parse::<f32>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(Error::Param(format!(
                "parameter {key} = `{v}` is not a finite number"
            ))),
        }
    }
}

/// Any number, the infinities included (`p_m = inf`: a threshold never reached), never NaN.
impl ParamValue for f64 {
    fn parse_param(key: &str, v: &str) -> Result<f64> {
        let x: f64 = match v {
            "inf" | "+inf" | "infinity" => f64::INFINITY,
            _ => v
                .parse()
                .map_err(|_| Error::Param(format!("parameter {key} = `{v}` is not a number")))?,
        };
        if x.is_nan() {
            return Err(Error::Param(format!(
                "parameter {key} = `{v}` must not be NaN"
            )));
        }
        Ok(x)
    }
}

/// A number in `lo..=hi` (the full range of the type where the method takes any value).
pub struct ParamDecl<T> {
    pub(crate) key: &'static str,
    pub(crate) default: &'static str,
    pub(crate) lo: T,
    pub(crate) hi: T,
    pub(crate) help: &'static str,
    /// What a valid value is, where the method says it in its own words: then a value that does
    /// not parse or lies outside `lo..=hi` is told `key = `text`: why` instead of the type's
    /// message or the bare range.
    pub(crate) why: Option<&'static str>,
}

impl<T: ParamValue> ParamDecl<T> {
    pub(crate) const fn new(
        key: &'static str,
        default: &'static str,
        lo: T,
        hi: T,
        help: &'static str,
    ) -> Self {
        ParamDecl {
            key,
            default,
            lo,
            hi,
            help,
            why: None,
        }
    }
    /// The same declaration, its refusals worded by `why` (what a valid value is).
    pub(crate) const fn why(self, why: &'static str) -> Self {
        ParamDecl {
            why: Some(why),
            ..self
        }
    }
    /// The line `penumbra methods` lists.
    pub(crate) const fn param(&self) -> Param {
        Param {
            key: self.key,
            default: self.default,
            help: self.help,
        }
    }
    /// The listed line with another method's help (one parser reads it for several methods).
    pub(crate) const fn param_with_help(&self, help: &'static str) -> Param {
        Param {
            key: self.key,
            default: self.default,
            help,
        }
    }
    /// The given value, or the default, parsed and checked against the range; `method` names the
    /// method in the range's message (`regular: n = 0 is outside 1..=128`).
    pub(crate) fn get(&self, p: &ParamMap, method: &str) -> Result<T> {
        self.read(p.get(self.key).map_or(self.default, String::as_str), method)
    }
    /// `text` parsed and checked against the range.
    fn read(&self, text: &str, method: &str) -> Result<T> {
        let value = T::parse_param(self.key, text)
            .and_then(|v| check_range(method, self.key, v, self.lo, self.hi));
        match self.why {
            Some(why) if value.is_err() => Err(Error::Param(format!(
                "{method}: {} = `{text}`: {why}",
                self.key
            ))),
            _ => value,
        }
    }
}

/// A number that may be left out: its listed default says what leaving it out does (`none`,
/// `32 per pixel`), so only a given value is parsed.
pub(crate) struct OptionalDecl<T>(ParamDecl<T>);

impl<T: ParamValue> OptionalDecl<T> {
    pub(crate) const fn new(
        key: &'static str,
        absent: &'static str,
        lo: T,
        hi: T,
        help: &'static str,
    ) -> Self {
        OptionalDecl(ParamDecl::new(key, absent, lo, hi, help))
    }
    pub(crate) const fn why(self, why: &'static str) -> Self {
        OptionalDecl(self.0.why(why))
    }
    pub(crate) const fn key(&self) -> &'static str {
        self.0.key
    }
    pub(crate) const fn param(&self) -> Param {
        self.0.param()
    }
    /// The given value parsed and checked against the range; None when it is not given.
    pub(crate) fn get(&self, p: &ParamMap, method: &str) -> Result<Option<T>> {
        p.get(self.0.key)
            .map(|text| self.0.read(text, method))
            .transpose()
    }
}

/// One of a fixed list of words.
pub struct ChoiceDecl {
    pub(crate) key: &'static str,
    pub(crate) default: &'static str,
    pub(crate) choices: &'static [&'static str],
    pub(crate) help: &'static str,
}

impl ChoiceDecl {
    pub(crate) const fn new(
        key: &'static str,
        default: &'static str,
        choices: &'static [&'static str],
        help: &'static str,
    ) -> Self {
        ChoiceDecl {
            key,
            default,
            choices,
            help,
        }
    }
    pub(crate) const fn param(&self) -> Param {
        Param {
            key: self.key,
            default: self.default,
            help: self.help,
        }
    }
    /// The given word, or the default, as one of the choices.
    pub(crate) fn get(&self, p: &ParamMap) -> Result<&'static str> {
        let v = p.get(self.key).map_or(self.default, String::as_str);
        self.choices
            .iter()
            .find(|c| **c == v)
            .copied()
            .ok_or_else(|| {
                Error::Param(format!(
                    "parameter {} = `{v}`: use one of {}",
                    self.key,
                    self.choices.join(", ")
                ))
            })
    }
}

/// One of a fixed list of words, each standing for a value of `T` (an enum): the parser and the
/// label read the same table. A bad word is told `key = `v`: use `a`, `b` or `c`` (table order).
pub(crate) struct WordDecl<T: 'static> {
    pub(crate) key: &'static str,
    pub(crate) default: &'static str,
    pub(crate) words: &'static [(&'static str, T)],
    pub(crate) help: &'static str,
}

impl<T: Copy + PartialEq> WordDecl<T> {
    pub(crate) const fn new(
        key: &'static str,
        default: &'static str,
        words: &'static [(&'static str, T)],
        help: &'static str,
    ) -> Self {
        WordDecl {
            key,
            default,
            words,
            help,
        }
    }
    pub(crate) const fn param(&self) -> Param {
        Param {
            key: self.key,
            default: self.default,
            help: self.help,
        }
    }
    /// The given word's value, or the default's.
    pub(crate) fn get(&self, p: &ParamMap) -> Result<T> {
        self.read(p.get(self.key).map_or(self.default, String::as_str))
    }
    /// The given word's value; None when it is not given (a listed default such as `none` that
    /// stands for no word at all).
    pub(crate) fn given(&self, p: &ParamMap) -> Result<Option<T>> {
        p.get(self.key).map(|v| self.read(v)).transpose()
    }
    /// The word that stands for `value`, if one does.
    pub(crate) fn word(&self, value: T) -> Option<&'static str> {
        self.words
            .iter()
            .find(|(_, v)| *v == value)
            .map(|(w, _)| *w)
    }
    fn read(&self, v: &str) -> Result<T> {
        if let Some((_, value)) = self.words.iter().find(|(w, _)| *w == v) {
            return Ok(*value);
        }
        let quoted: Vec<String> = self.words.iter().map(|(w, _)| format!("`{w}`")).collect();
        let choices = match quoted.split_last() {
            Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
            _ => quoted.join(""),
        };
        Err(Error::Param(format!("{} = `{v}`: use {choices}", self.key)))
    }
}

/// `on` or `off` (and, where the method also takes them, `true` or `false`).
pub struct SwitchDecl {
    pub(crate) key: &'static str,
    pub(crate) default: &'static str,
    pub(crate) help: &'static str,
    /// `true` and `false` are taken too (the adaptive method's switches, as a TOML grid's
    /// booleans arrive).
    pub(crate) true_false: bool,
}

impl SwitchDecl {
    pub(crate) const fn new(key: &'static str, on: bool, help: &'static str) -> Self {
        SwitchDecl {
            key,
            default: if on { "on" } else { "off" },
            help,
            true_false: false,
        }
    }
    /// The same switch, taking `true` and `false` as well.
    pub(crate) const fn or_true_false(self) -> Self {
        SwitchDecl {
            true_false: true,
            ..self
        }
    }
    pub(crate) const fn param(&self) -> Param {
        Param {
            key: self.key,
            default: self.default,
            help: self.help,
        }
    }
    /// The given switch, or the default; `method` names the method in the message.
    pub(crate) fn get(&self, p: &ParamMap, method: &str) -> Result<bool> {
        self.read(p.get(self.key).map_or(self.default, String::as_str), method)
    }
    /// The given switch; None when it is not given.
    pub(crate) fn given(&self, p: &ParamMap, method: &str) -> Result<Option<bool>> {
        p.get(self.key).map(|v| self.read(v, method)).transpose()
    }
    fn read(&self, v: &str, method: &str) -> Result<bool> {
        match v {
            "on" => Ok(true),
            "off" => Ok(false),
            "true" if self.true_false => Ok(true),
            "false" if self.true_false => Ok(false),
            v => Err(Error::Param(format!(
                "{method}: {} = `{v}`: use `on` or `off`",
                self.key
            ))),
        }
    }
}

/// Every converted declaration's default, for the test that each parses within its range or
/// choices: (method, key, the default's check).
#[cfg(test)]
pub(crate) fn all_defaults() -> Vec<(&'static str, Result<()>)> {
    use super::*;
    let int = |d: &ParamDecl<u32>| (d.key, d.get(&ParamMap::new(), "default").map(|_| ()));
    let num = |d: &ParamDecl<f32>| (d.key, d.get(&ParamMap::new(), "default").map(|_| ()));
    let word = |d: &ChoiceDecl| (d.key, d.get(&ParamMap::new()).map(|_| ()));
    let switch = |d: &SwitchDecl| (d.key, d.get(&ParamMap::new(), "default").map(|_| ()));
    let wide = |d: &ParamDecl<f64>| (d.key, d.get(&ParamMap::new(), "default").map(|_| ()));
    fn words<T: Copy + PartialEq>(d: &WordDecl<T>) -> (&'static str, Result<()>) {
        (d.key, d.get(&ParamMap::new()).map(|_| ()))
    }
    vec![
        int(&fixed_samples::N),
        word(&pcf::KERNEL),
        num(&pcf::RADIUS),
        num(&pcf::DARKENING),
        int(&pcss::TAPS),
        int(&pcss::BLOCKER_TAPS),
        num(&pcss::MAX_RADIUS),
        int(&environment::pixels::AO_SAMPLES),
        num(&environment::pixels::AO_RADIUS),
        word(&environment::pixels::AT),
        int(&cascades::N),
        word(&cascades::SPLIT),
        num(&cascades::LAMBDA),
        word(&cascades::FILTER),
        num(&filtered::C),
        num(&filtered::BLEED),
        num(&filtered::C_POS),
        num(&filtered::C_NEG),
        num(&filtered::MOMENT_BIAS),
        int(&filtered::ORDER),
        int(&environment::shadowmaps::K),
        word(&environment::shadowmaps::FILTER),
        int(&environment::shadowmaps::PCF_RADIUS),
        int(&environment::adaptive::MAX_LEVEL),
        int(&environment::adaptive::P_M),
        num(&environment::adaptive::CONTRAST),
        num(&environment::adaptive::MIN_SHARE),
        int(&environment::adaptive::COUNT_STRIDE),
        num(&auto::TARGET),
        int(&auto::MAX_N),
        int(&auto::MAX_SIZE),
        word(&auto::COST),
        int(&auto::PIXELS),
        num(&auto::DELTA),
        num(&regions::TARGET),
        int(&regions::MAX_N),
        int(&regions::MIN_SIZE),
        int(&regions::MAX_SIZE),
        num(&regions::DENSITY),
        int(&regions::REGION),
        int(&regions::CENTRE_SIZE),
        int(&regions::BLOCKER_TAPS),
        num(&regions::MAP_COST),
        num(&regions::SAMPLE_COST),
        int(&regions::FORCE_SIZE),
        int(&regions::PIXELS),
        num(&regions::DELTA),
        num(&regions::PLAN_TARGET),
        switch(&fixed_samples::CULL),
        switch(&fixed_samples::ESTIMATE),
        switch(&regions::MERGE),
        switch(&regions::HOLD),
        switch(&regions::CERTIFY),
        switch(&environment::pixels::SSAO),
        wide(&adaptive::params::P_M),
        wide(&adaptive::params::GROWTH),
        int(&adaptive::params::MAX_LEVEL),
        words(&adaptive::params::WEIGHTS),
        words(&adaptive::params::SCOPE),
        words(&adaptive::params::LAYOUT),
        switch(&adaptive::params::SCISSOR),
        words(&adaptive::params::STEER),
        switch(&adaptive::params::CULL),
        int(&adaptive::params::HOLD),
        switch(&adaptive::params::ITEMS_GROW),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_declared_default_parses_within_its_range() {
        let all = all_defaults();
        assert!(all.len() >= 52, "{} declarations", all.len());
        for (key, check) in all {
            assert!(check.is_ok(), "{key}: {check:?}");
        }
    }

    #[test]
    fn a_default_outside_its_range_or_not_a_number_fails() {
        let out = ParamDecl::<u32>::new("n", "0", 1, 128, "");
        assert_eq!(
            out.get(&ParamMap::new(), "default")
                .unwrap_err()
                .to_string(),
            "default: n = 0 is outside 1..=128"
        );
        let bad = ParamDecl::<f32>::new("r", "0.O5", 0.0, 1.0, "");
        assert!(bad.get(&ParamMap::new(), "default").is_err());
        let word = ChoiceDecl::new("k", "pisson", &["poisson"], "");
        assert!(word.get(&ParamMap::new()).is_err());
    }

    #[test]
    fn given_values_are_parsed_and_checked_with_the_usual_words() {
        let n = ParamDecl::<u32>::new("n", "17", 1, 128, "");
        let p = |k: &str, v: &str| ParamMap::from([(k.to_string(), v.to_string())]);
        assert_eq!(n.get(&ParamMap::new(), "regular").unwrap(), 17);
        assert_eq!(n.get(&p("n", "5"), "regular").unwrap(), 5);
        assert_eq!(
            n.get(&p("n", "-1"), "regular").unwrap_err().to_string(),
            "parameter n = `-1` is not a non-negative integer"
        );
        assert_eq!(
            n.get(&p("n", "200"), "regular").unwrap_err().to_string(),
            "regular: n = 200 is outside 1..=128"
        );
        let r = ParamDecl::<f32>::new("radius", "2", 0.0, 64.0, "");
        assert_eq!(r.get(&ParamMap::new(), "pcf").unwrap(), 2.0);
        assert_eq!(
            r.get(&p("radius", "inf"), "pcf").unwrap_err().to_string(),
            "parameter radius = `inf` is not a finite number"
        );
        let c = ChoiceDecl::new("kernel", "poisson", &["box", "poisson"], "");
        assert_eq!(c.get(&p("kernel", "box")).unwrap(), "box");
        assert_eq!(
            c.get(&p("kernel", "x")).unwrap_err().to_string(),
            "parameter kernel = `x`: use one of box, poisson"
        );
    }
}

/// The listing's defaults against the parsers, for every method in the registry (converted or
/// not): a method parsed with no parameters equals the method parsed with each listed default
/// given explicitly.
#[cfg(test)]
mod round_trip {
    use super::super::{Method, REGISTRY};

    /// Listed defaults that describe a behaviour rather than a value a user could write.
    const NOT_VALUES: &[(&str, &str)] = &[
        ("pcf", "spread"),
        ("adaptive", "preset"),
        ("adaptive", "p_share"),
        ("adaptive", "tol"),
        ("adaptive", "items"),
        ("env-shadowmaps", "taps"),
        // Given at all, it needs scope = local (the listed `on` is what local scope does).
        ("adaptive", "items_grow"),
        // Absent it is recorded as unset (`"cull": null`), which runs as `off`; given, as `false`.
        ("adaptive", "cull"),
    ];

    #[test]
    fn every_methods_listed_defaults_parse_to_its_defaults() {
        let (mut checked, mut wrong) = (0, Vec::new());
        for info in REGISTRY {
            let plain = Method::parse(info.name, &[]).unwrap();
            let given: Vec<String> = info
                .params
                .iter()
                .filter(|p| !NOT_VALUES.contains(&(info.name, p.key)))
                .map(|p| format!("{}={}", p.key, p.default))
                .collect();
            checked += given.len();
            // Each default alone, then all of them together.
            let mut specs: Vec<String> =
                given.iter().map(|g| format!("{}:{g}", info.name)).collect();
            specs.push(format!("{}:{}", info.name, given.join(",")));
            for spec in specs {
                match Method::parse(&spec, &[]) {
                    Err(e) => wrong.push(format!("{spec}: {e}")),
                    Ok(m)
                        if m.params_json() != plain.params_json() || m.label() != plain.label() =>
                    {
                        wrong.push(format!(
                            "{spec}: {} against {}",
                            m.params_json(),
                            plain.params_json()
                        ))
                    }
                    Ok(_) => {}
                }
            }
        }
        assert!(wrong.is_empty(), "{}", wrong.join("\n"));
        assert!(checked >= 80, "{checked} defaults checked");
    }
}
