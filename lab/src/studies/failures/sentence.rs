//! The gallery's one-sentence statement of a failure, generated from the measured figures only.

use serde::{Deserialize, Serialize};

/// What one method measured on one failure scene.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Figures {
    pub label: String,
    pub method: String,
    pub shadow_maps: u32,
    pub rmse: f64,
    /// Geometry pixels.
    pub pixels: u64,
    /// Pixels where V exceeds the reference by more than 1/32, with the mean V and mean reference there.
    pub bright: u64,
    pub bright_v: f64,
    pub bright_ref: f64,
    /// Pixels where V falls short of the reference by more than 1/32, likewise.
    pub dark: u64,
    pub dark_v: f64,
    pub dark_ref: f64,
}

impl Figures {
    pub fn off(&self) -> u64 {
        self.bright + self.dark
    }
}

/// The smaller side (too bright or too dark) is stated too from this share of the geometry, in %.
pub const MINOR_SIDE_PERCENT: f64 = 0.5;

/// Which method a scene's sentence is about, and how its failure reads.
#[derive(Debug, Clone, Copy)]
pub struct Framing {
    /// Only methods of this name are candidates (`None`: any but `hard`, whose error is the
    /// missing penumbra everywhere).
    pub subject: Option<&'static str>,
    /// Said of a method that is too bright / too dark, e.g. "misses the pole".
    pub bright: &'static str,
    pub dark: &'static str,
}

impl Default for Framing {
    fn default() -> Self {
        Framing {
            subject: None,
            bright: "is too bright",
            dark: "is too dark",
        }
    }
}

/// "adaptive:p_m=0 misses the pole: V = 1.00 where the reference is 0.72 in 2301 pixels (24.1% of
/// the geometry); regular:n=17 is off by more than 1/32 in 12 pixels." The subject is the candidate
/// with the most pixels off by more than 1/32; its larger side (too bright or too dark) is stated,
/// and the other side when it covers at least `MINOR_SIDE_PERCENT` of the geometry.
pub fn sentence(framing: &Framing, figures: &[Figures]) -> String {
    let candidates: Vec<&Figures> = figures
        .iter()
        .filter(|f| match framing.subject {
            Some(name) => f.method == name,
            None => f.method != "hard",
        })
        .collect();
    // The first of the worst (list order), so ties name the earlier method.
    let mut subject: Option<&Figures> = None;
    for f in &candidates {
        if subject.is_none_or(|s| f.off() > s.off() || (f.off() == s.off() && f.rmse > s.rmse)) {
            subject = Some(f);
        }
    }
    let Some(s) = subject.or_else(|| figures.first()) else {
        return "No method was measured.".into();
    };
    // Candidates with the very same counts fail the same way: name them with the subject.
    let same: Vec<&str> = candidates
        .iter()
        .filter(|f| f.label != s.label && f.bright == s.bright && f.dark == s.dark)
        .map(|f| f.label.as_str())
        .collect();
    let who = if same.is_empty() {
        s.label.clone()
    } else {
        format!("{} (likewise {})", s.label, same.join(", "))
    };
    if s.off() == 0 {
        return format!(
            "{} stays within 1/32 of the reference at every pixel here (RMSE {:.4}): the failure does not show at this resolution.",
            s.label, s.rmse
        );
    }
    let bright = (framing.bright, s.bright, s.bright_v, s.bright_ref);
    let dark = (framing.dark, s.dark, s.dark_v, s.dark_ref);
    let (main, other) = if s.bright >= s.dark {
        (bright, dark)
    } else {
        (dark, bright)
    };
    let share = |n: u64| {
        if s.pixels == 0 {
            0.0
        } else {
            100.0 * n as f64 / s.pixels as f64
        }
    };
    let (phrase, n, v, r) = main;
    let mut text = format!(
        "{who} {phrase}: V = {v:.2} where the reference is {r:.2} in {n} pixels ({:.1}% of the geometry)",
        share(n)
    );
    // The other side too, when it is no stray handful.
    let (phrase, n, v, r) = other;
    if share(n) >= MINOR_SIDE_PERCENT {
        text += &format!(", and {phrase}: V = {v:.2} where the reference is {r:.2} in {n} pixels");
    }
    let best = figures
        .iter()
        .filter(|f| f.label != s.label && !same.contains(&f.label.as_str()))
        .min_by(|a, b| a.off().cmp(&b.off()).then(a.rmse.total_cmp(&b.rmse)));
    if let Some(b) = best {
        text += &format!(
            "; {} is off by more than 1/32 in {} pixels",
            b.label,
            b.off()
        );
    }
    text + "."
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fig(label: &str, method: &str, bright: u64, dark: u64) -> Figures {
        Figures {
            label: label.into(),
            method: method.into(),
            pixels: 1000,
            bright,
            bright_v: 1.0,
            bright_ref: 0.7234,
            dark,
            dark_v: 0.25,
            dark_ref: 0.9,
            rmse: (bright + dark) as f64 / 1e4,
            ..Default::default()
        }
    }

    #[test]
    fn the_subject_method_too_bright() {
        let framing = Framing {
            subject: Some("adaptive"),
            bright: "misses the pole",
            dark: "is too dark",
        };
        // hard is worse, but the framing asks about the adaptive methods; of those, the worse one.
        let figs = [
            fig("hard", "hard", 500, 400),
            fig("regular:n=17", "regular", 3, 9),
            fig("adaptive:p_m=0", "adaptive", 241, 2),
            fig("adaptive:scope=local", "adaptive", 100, 0),
        ];
        assert_eq!(
            sentence(&framing, &figs),
            "adaptive:p_m=0 misses the pole: V = 1.00 where the reference is 0.72 in 241 pixels (24.1% of the geometry); \
             regular:n=17 is off by more than 1/32 in 12 pixels."
        );
    }

    #[test]
    fn any_method_but_hard_too_dark() {
        let framing = Framing {
            dark: "shows acne on the ground",
            ..Framing::default()
        };
        let figs = [
            fig("hard", "hard", 0, 900),
            fig("regular:n=5", "regular", 10, 300),
            fig("adaptive:p_m=0", "adaptive", 5, 120),
        ];
        assert_eq!(
            sentence(&framing, &figs),
            "regular:n=5 shows acne on the ground: V = 0.25 where the reference is 0.90 in 300 pixels (30.0% of the geometry), \
             and is too bright: V = 1.00 where the reference is 0.72 in 10 pixels; adaptive:p_m=0 is off by more than 1/32 in 125 pixels."
        );
    }

    #[test]
    fn methods_that_fail_identically_are_named_together() {
        let framing = Framing {
            dark: "shows acne on the lit ground",
            ..Framing::default()
        };
        let figs = [
            fig("hard", "hard", 0, 900),
            fig("regular:n=17", "regular", 2, 300),
            fig("adaptive:p_m=0", "adaptive", 2, 300),
            fig("local", "adaptive", 1, 40),
        ];
        assert_eq!(
            sentence(&framing, &figs),
            "regular:n=17 (likewise adaptive:p_m=0) shows acne on the lit ground: V = 0.25 where the reference is 0.90 in 300 pixels \
             (30.0% of the geometry); local is off by more than 1/32 in 41 pixels."
        );
    }

    #[test]
    fn no_failure_is_said_so() {
        let figs = [fig("adaptive:p_m=0", "adaptive", 0, 0)];
        assert_eq!(
            sentence(&Framing::default(), &figs),
            "adaptive:p_m=0 stays within 1/32 of the reference at every pixel here (RMSE 0.0000): the failure does not show at this resolution."
        );
        assert_eq!(
            sentence(&Framing::default(), &[]),
            "No method was measured."
        );
    }
}
