//! [`Metric`]: every metric a run can evaluate, the six geometry metrics of
//! `sceneeval-plausibility`, physical stability (`sceneeval-physics`, feature `physics`) and
//! the four text-fidelity metrics of `sceneeval-fidelity`, under one name each, with the
//! summary's column names as aliases.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use sceneeval_fidelity::FidelityMetric;
use sceneeval_plausibility as plausibility;

/// A metric of an evaluation plan: `--plan LIST`, `--metrics`, the plan file's `metrics`.
///
/// Each crate that computes metrics has its own dispatcher key ([`plausibility::Metric`],
/// [`FidelityMetric`]); this is the one list over all of them, in the order they are reported
/// (the geometry metrics, stability, then CNT, ATR, OOR, OAR). [`Metric::Stability`] is
/// parsed in every build; a plan that runs it needs the evaluator's `physics` feature. Names are
/// snake case; the summary's column names are accepted too, in any case (`OOB`, `COL_ob`,
/// `DOOR_blk`, `cnt`):
///
/// ```
/// use sceneeval_results::Metric;
/// assert_eq!("out_of_bounds".parse::<Metric>().unwrap(), Metric::OutOfBounds);
/// assert_eq!("OOB".parse::<Metric>().unwrap(), Metric::OutOfBounds);
/// assert_eq!("cnt".parse::<Metric>().unwrap(), Metric::Cnt);
/// let err = "colision".parse::<Metric>().unwrap_err().to_string();
/// assert!(err.contains("did you mean \"collision\""), "{err}");
/// assert!(err.contains("stability, cnt, atr, oor, oar"), "{err}");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Metric {
    /// Object collision (COL_ob, COL_sc).
    Collision,
    /// Object support (SUP).
    Support,
    /// Scene navigability (NAV).
    Navigability,
    /// Accessibility of functional sides (ACC).
    Accessibility,
    /// Objects out of bounds (OOB).
    OutOfBounds,
    /// Door and window clearance (DOOR_blk, WIN_blk; reference v1.1).
    OpeningClearance,
    /// Physical stability under a rigid-body simulation (STAB; `sceneeval-physics`, feature
    /// `physics`; not in the paper).
    Stability,
    /// Object counts (CNT).
    Cnt,
    /// Object attributes, judged by a VLM (ATR).
    Atr,
    /// Object-object relationships (OOR).
    Oor,
    /// Object-architecture relationships (OAR).
    Oar,
}

impl Metric {
    /// Every metric, in the order they are reported.
    pub const ALL: [Metric; 11] = [
        Metric::Collision,
        Metric::Support,
        Metric::Navigability,
        Metric::Accessibility,
        Metric::OutOfBounds,
        Metric::OpeningClearance,
        Metric::Stability,
        Metric::Cnt,
        Metric::Atr,
        Metric::Oor,
        Metric::Oar,
    ];

    /// The metric computed by `sceneeval-plausibility`, if this is one.
    pub const fn geometry(self) -> Option<plausibility::Metric> {
        Some(match self {
            Metric::Collision => plausibility::Metric::Collision,
            Metric::Support => plausibility::Metric::Support,
            Metric::Navigability => plausibility::Metric::Navigability,
            Metric::Accessibility => plausibility::Metric::Accessibility,
            Metric::OutOfBounds => plausibility::Metric::OutOfBounds,
            Metric::OpeningClearance => plausibility::Metric::OpeningClearance,
            Metric::Stability | Metric::Cnt | Metric::Atr | Metric::Oor | Metric::Oar => return None,
        })
    }

    /// The metric computed by `sceneeval-fidelity`, if this is one.
    pub const fn fidelity(self) -> Option<FidelityMetric> {
        Some(match self {
            Metric::Cnt => FidelityMetric::Cnt,
            Metric::Atr => FidelityMetric::Atr,
            Metric::Oor => FidelityMetric::Oor,
            Metric::Oar => FidelityMetric::Oar,
            _ => return None,
        })
    }

    /// The snake-case name used in plan files, reports and on the command line.
    pub const fn name(self) -> &'static str {
        match (self.geometry(), self.fidelity()) {
            (Some(g), _) => g.name(),
            (_, Some(f)) => f.name(),
            // The one metric of neither kind.
            (None, None) => "stability",
        }
    }

    /// The summary's columns of this metric (`summary.csv`, `summary.md`).
    pub const fn columns(self) -> &'static [&'static str] {
        match self {
            Metric::Collision => &["COL_ob", "COL_sc"],
            Metric::Support => &["SUP"],
            Metric::Navigability => &["NAV"],
            Metric::Accessibility => &["ACC"],
            Metric::OutOfBounds => &["OOB"],
            Metric::OpeningClearance => &["DOOR_blk", "WIN_blk"],
            Metric::Stability => &["STAB"],
            Metric::Cnt => &["CNT"],
            Metric::Atr => &["ATR"],
            Metric::Oor => &["OOR"],
            Metric::Oar => &["OAR"],
        }
    }

    /// The metrics in the order of the summary tables (`summary.csv`, `summary.md`, the
    /// comparisons and the report): the text-fidelity metrics first, as in the paper's tables,
    /// then the others in the order of [`Metric::ALL`].
    pub fn table_order() -> impl Iterator<Item = Metric> {
        let fidelity = Metric::ALL.into_iter().filter(|m| m.fidelity().is_some());
        let others = Metric::ALL.into_iter().filter(|m| m.fidelity().is_none());
        fidelity.chain(others)
    }

    /// Every summary column with its metric, in table order ([`Metric::table_order`], each
    /// metric's [`Metric::columns`]): the one list every table of the workspace is made from.
    ///
    /// ```
    /// use sceneeval_results::Metric;
    /// let columns: Vec<&str> = Metric::summary_columns().into_iter().map(|(c, _)| c).collect();
    /// assert_eq!(&columns[..5], ["CNT", "ATR", "OOR", "OAR", "COL_ob"]);
    /// assert_eq!(columns.last(), Some(&"STAB"));
    /// ```
    pub fn summary_columns() -> Vec<(&'static str, Metric)> {
        Metric::table_order()
            .flat_map(|m| m.columns().iter().map(move |&c| (c, m)))
            .collect()
    }

    /// The metric named `name` or one of its columns, ignoring ASCII case, surrounding
    /// spaces, and `-` for `_`; `None` when there is none.
    pub fn from_name(name: &str) -> Option<Metric> {
        let key = name.trim().replace('-', "_");
        Metric::ALL.into_iter().find(|m| {
            m.name().eq_ignore_ascii_case(&key) || m.columns().iter().any(|c| c.eq_ignore_ascii_case(&key))
        })
    }

    /// The metric whose name (or column) is closest to `name`, when one is close enough to be
    /// a typo of it (a Jaro-Winkler similarity of at least 0.8, the measure clap uses for its
    /// own suggestions).
    pub fn closest(name: &str) -> Option<Metric> {
        let key = name.trim().to_ascii_lowercase();
        let key = key.as_str();
        Metric::ALL
            .into_iter()
            .flat_map(|m| {
                std::iter::once(m.name())
                    .chain(m.columns().iter().copied())
                    .map(move |n| (m, strsim::jaro_winkler(key, &n.to_ascii_lowercase())))
            })
            .filter(|(_, s)| *s >= 0.8)
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(m, _)| m)
    }

    /// Which way the metric's summary columns improve: higher for SUP, NAV, ACC, STAB, CNT,
    /// ATR, OOR, OAR; lower for COL_ob, COL_sc, OOB, DOOR_blk, WIN_blk (every column of a metric
    /// improves the same way).
    ///
    /// ```
    /// use sceneeval_results::{Better, Metric};
    /// assert_eq!(Metric::Support.better(), Better::Higher);
    /// assert_eq!(Metric::Collision.better(), Better::Lower);
    /// assert!(Better::Lower.prefers(2.0, 5.0));
    /// ```
    pub const fn better(self) -> Better {
        match self {
            Metric::Support
            | Metric::Navigability
            | Metric::Accessibility
            | Metric::Stability
            | Metric::Cnt
            | Metric::Atr
            | Metric::Oor
            | Metric::Oar => Better::Higher,
            Metric::Collision | Metric::OutOfBounds | Metric::OpeningClearance => Better::Lower,
        }
    }

    /// The list of metric names for messages: "collision, support, ..., cnt, atr, oor, oar".
    pub fn names() -> String {
        Metric::ALL.map(Metric::name).join(", ")
    }
}

impl fmt::Display for Metric {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Which way a metric improves ([`Metric::better`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Better {
    /// Higher values are better (a share of satisfied specs, of supported objects, ...).
    Higher,
    /// Lower values are better (a share of objects in collision, out of bounds, ...).
    Lower,
}

impl Better {
    /// Whether `a` is strictly better than `b` in this direction.
    pub fn prefers(self, a: f64, b: f64) -> bool {
        match self {
            Better::Higher => a > b,
            Better::Lower => a < b,
        }
    }

    /// `higher` or `lower`.
    pub const fn name(self) -> &'static str {
        match self {
            Better::Higher => "higher",
            Better::Lower => "lower",
        }
    }
}

/// A metric name that names no metric; its message lists the metrics and suggests the
/// closest one.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "unknown metric {name:?}{}; the metrics are {} (or their summary columns, e.g. OOB)",
    suggestion.map(|m| format!(" (did you mean {:?}?)", m.name())).unwrap_or_default(),
    Metric::names()
)]
pub struct UnknownMetric {
    /// The name given.
    pub name: String,
    /// The metric it is probably a typo of.
    pub suggestion: Option<Metric>,
}

impl FromStr for Metric {
    type Err = UnknownMetric;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Metric::from_name(s).ok_or_else(|| UnknownMetric {
            name: s.to_owned(),
            suggestion: Metric::closest(s),
        })
    }
}

impl Serialize for Metric {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for Metric {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let name = String::deserialize(deserializer)?;
        name.parse().map_err(serde::de::Error::custom)
    }
}

impl From<plausibility::Metric> for Metric {
    fn from(m: plausibility::Metric) -> Self {
        match m {
            plausibility::Metric::Collision => Metric::Collision,
            plausibility::Metric::Support => Metric::Support,
            plausibility::Metric::Navigability => Metric::Navigability,
            plausibility::Metric::Accessibility => Metric::Accessibility,
            plausibility::Metric::OutOfBounds => Metric::OutOfBounds,
            plausibility::Metric::OpeningClearance => Metric::OpeningClearance,
        }
    }
}

impl From<FidelityMetric> for Metric {
    fn from(m: FidelityMetric) -> Self {
        match m {
            FidelityMetric::Cnt => Metric::Cnt,
            FidelityMetric::Atr => Metric::Atr,
            FidelityMetric::Oor => Metric::Oor,
            FidelityMetric::Oar => Metric::Oar,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_metric_round_trips_through_its_name_and_its_kind() {
        for m in Metric::ALL {
            assert_eq!(m.name().parse::<Metric>().unwrap(), m);
            assert_eq!(m.name().to_uppercase().parse::<Metric>().unwrap(), m);
            for c in m.columns() {
                assert_eq!(c.parse::<Metric>().unwrap(), m, "{c}");
            }
            assert_eq!(serde_json::to_string(&m).unwrap(), format!("\"{}\"", m.name()));
            assert_eq!(serde_json::from_str::<Metric>(&format!("\"{m}\"")).unwrap(), m);
            match (m.geometry(), m.fidelity()) {
                (Some(g), None) => assert_eq!(Metric::from(g), m),
                (None, Some(f)) => assert_eq!(Metric::from(f), m),
                (None, None) => assert_eq!(m, Metric::Stability),
                other => panic!("{m}: {other:?}"),
            }
        }
        assert_eq!(
            "opening-clearance".parse::<Metric>().unwrap(),
            Metric::OpeningClearance
        );
        assert_eq!(" win_blk ".parse::<Metric>().unwrap(), Metric::OpeningClearance);
        assert_eq!("STAB".parse::<Metric>().unwrap(), Metric::Stability);
        assert_eq!("stability".parse::<Metric>().unwrap(), Metric::Stability);
        // The plausibility crate's order is this order's prefix.
        let geometry: Vec<Metric> = plausibility::Metric::ALL.into_iter().map(Metric::from).collect();
        assert_eq!(geometry, Metric::ALL[..6]);
    }

    #[test]
    fn the_direction_of_each_metric_is_the_summary_legend_s() {
        // summary's LEGEND: lower is better for COL_ob, COL_sc, OOB, DOOR_blk and WIN_blk;
        // higher for SUP, NAV, ACC and CNT, ATR, OOR, OAR.
        let lower = ["COL_ob", "COL_sc", "OOB", "DOOR_blk", "WIN_blk"];
        for m in Metric::ALL {
            for c in m.columns() {
                assert_eq!(m.better() == Better::Lower, lower.contains(c), "{c}");
                assert!(crate::LEGEND.contains(c), "{c}");
            }
        }
        assert!(Better::Higher.prefers(2.0, 1.0) && !Better::Higher.prefers(1.0, 1.0));
        assert!(Better::Lower.prefers(1.0, 2.0) && !Better::Lower.prefers(2.0, 2.0));
    }

    #[test]
    fn unknown_names_list_the_metrics_and_suggest_the_closest() {
        let e = "oob2".parse::<Metric>().unwrap_err();
        assert_eq!(e.suggestion, Some(Metric::OutOfBounds));
        for (typo, meant) in [
            ("colision", Metric::Collision),
            ("navigation", Metric::Navigability),
            ("acessibility", Metric::Accessibility),
            ("out_of_bound", Metric::OutOfBounds),
            ("suport", Metric::Support),
        ] {
            assert_eq!("x".parse::<Metric>().ok(), None);
            assert_eq!(
                typo.parse::<Metric>().unwrap_err().suggestion,
                Some(meant),
                "{typo}"
            );
        }
        let e = "physics".parse::<Metric>().unwrap_err();
        assert_eq!(e.suggestion, None);
        assert_eq!(
            e.to_string(),
            "unknown metric \"physics\"; the metrics are collision, support, navigability, accessibility, \
             out_of_bounds, opening_clearance, stability, cnt, atr, oor, oar (or their summary columns, e.g. OOB)"
        );
    }
}
