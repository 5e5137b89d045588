//! The page's settings: `display`'s flags, the light level and the view,
//! read from a URL's query exactly as from a command line (the same clap
//! definitions), so that a setting means one thing in both.

use std::collections::BTreeMap;

use anyhow::{anyhow, bail, Result};
use clap::{CommandFactory, FromArgMatches, Parser};

use crate::display::{on_off, VisionArgs};

/// What the page shows and how: the flags of `scotopia display`, plus
/// the light level and the view.
#[derive(clap::Args, Clone, Debug)]
pub struct Settings {
    #[command(flatten)]
    pub vision: VisionArgs,
    /// The light level: the scene as if every light were K times brighter
    /// (exact: light transport is linear). The page's slider spans 1e-4
    /// (starlight for a lit street) to 1e4 (daylight for a dim room).
    #[arg(long, default_value_t = 1.0, value_name = "K")]
    pub scale: f64,
    /// What the page shows first: seen (what the eye sees), stages (mode,
    /// glare, adaptation, night shift and the final image side by side)
    /// or false-colour (a map of --false-colour with a scale bar).
    #[arg(long, default_value = "seen", value_name = "seen|stages|false-colour")]
    pub view: String,
    /// The false-colour view's quantity.
    #[arg(
        long = "false-colour",
        default_value = "luminance",
        value_name = "luminance|mesopic|illuminance"
    )]
    pub false_colour: String,
    /// The false-colour range LO:HI (default: 0 to the 99th percentile).
    #[arg(long, value_name = "LO:HI")]
    pub range: Option<String>,
    /// A logarithmic false-colour scale.
    #[arg(long)]
    pub log: bool,
}

/// What a page asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    Seen,
    Stages,
    FalseColour,
}

impl Settings {
    /// The settings as flag → value, flags without dashes.
    pub fn pairs(&self) -> Pairs {
        let mut p: Pairs = self
            .vision
            .pairs()
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .collect();
        p.insert("scale".into(), self.scale.to_string());
        p.insert("view".into(), self.view.clone());
        p.insert("false-colour".into(), self.false_colour.clone());
        p.insert("log".into(), if self.log { "on" } else { "off" }.into());
        if let Some(r) = &self.range {
            p.insert("range".into(), r.clone());
        }
        p
    }

    /// The checked view and light level.
    pub fn view(&self) -> Result<(View, f32)> {
        let view = match self.view.as_str() {
            "seen" => View::Seen,
            "stages" => View::Stages,
            "false-colour" => View::FalseColour,
            v => bail!("--view {v}: use seen, stages or false-colour"),
        };
        // Checked in f32, where the pixels are multiplied by it.
        let k = crate::numbers::light_scale(self.scale).map_err(anyhow::Error::msg)?;
        Ok((view, k))
    }
}

/// Settings as flag → value (`scale` → `0.02`).
pub type Pairs = BTreeMap<String, String>;

#[derive(Parser)]
#[command(
    name = "settings",
    no_binary_name = true,
    args_override_self = true,
    disable_help_flag = true
)]
struct Query {
    #[command(flatten)]
    settings: Settings,
}

/// `base` with the `key=value`s of a URL query over it (keys as the
/// flags, with `-` or `_`), and the settings they make, checked as the
/// command line checks them. `skip`: keys that are not settings.
pub fn merge(base: &Pairs, query: &str, skip: &[&str]) -> Result<(Pairs, Settings)> {
    let given =
        form_urlencoded::parse(query.as_bytes()).map(|(k, v)| (k.into_owned(), v.into_owned()));
    merge_pairs(base, given, skip)
}

/// `base` with `given` over it, as [`merge`].
pub fn merge_pairs(
    base: &Pairs,
    given: impl IntoIterator<Item = (String, String)>,
    skip: &[&str],
) -> Result<(Pairs, Settings)> {
    let mut pairs = base.clone();
    for (k, v) in given {
        let key = k.replace('_', "-");
        if skip.contains(&key.as_str()) {
            continue;
        }
        if flag(&key).is_none() {
            bail!("unknown setting '{key}': use {}", names().join(", "));
        }
        pairs.insert(key, v);
    }
    let settings = parse(&pairs)?;
    Ok((pairs, settings))
}

/// Settings sent as a JSON object (`{"scale": 0.02, "glare": false}`):
/// strings as they are, numbers as written, true/false as on/off.
pub fn from_json(body: &[u8]) -> Result<Vec<(String, String)>> {
    let value: serde_json::Value =
        serde_json::from_slice(body).map_err(|e| anyhow!("the settings are not JSON ({e})"))?;
    let serde_json::Value::Object(map) = value else {
        bail!("the settings are not a JSON object of setting → value");
    };
    map.into_iter()
        .map(|(k, v)| {
            let text = match v {
                serde_json::Value::String(s) => s,
                serde_json::Value::Number(n) => n.to_string(),
                serde_json::Value::Bool(b) => if b { "on" } else { "off" }.into(),
                other => bail!("setting '{k}': {other} is not a value"),
            };
            Ok((k, text))
        })
        .collect()
}

/// The settings `pairs` make.
pub fn parse(pairs: &Pairs) -> Result<Settings> {
    let mut argv = Vec::new();
    for (k, v) in pairs {
        let takes_value = flag(k)
            .ok_or_else(|| anyhow!("unknown setting '{k}'"))?
            .get_action()
            .takes_values();
        if takes_value {
            // `--k=v`, so that a value may start with a dash.
            argv.push(format!("--{k}={v}"));
        } else if on_off(k, v)? {
            argv.push(format!("--{k}"));
        }
    }
    let matches = Query::command().try_get_matches_from(argv).map_err(|e| {
        let text = e.to_string();
        let first = text.lines().next().unwrap_or_default();
        anyhow!("{}", first.trim_start_matches("error: "))
    })?;
    Ok(Query::from_arg_matches(&matches)?.settings)
}

fn flag(long: &str) -> Option<clap::Arg> {
    Query::command()
        .get_arguments()
        .find(|a| a.get_long() == Some(long))
        .cloned()
}

fn names() -> Vec<String> {
    Query::command()
        .get_arguments()
        .filter_map(|a| a.get_long().map(String::from))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn defaults() -> Pairs {
        parse(&Pairs::new()).unwrap().pairs()
    }

    #[test]
    fn a_query_overrides_the_base_and_is_checked_like_the_command_line() {
        let (pairs, s) = merge(&defaults(), "scale=0.02&night_shift=off&hdr=on", &[]).unwrap();
        assert_eq!(s.scale, 0.02);
        assert_eq!(pairs["night-shift"], "off");
        assert_eq!(pairs["adaptation"], "global");
        assert!(s.vision.pairs().contains(&("hdr", "on".into())));
        // The pairs parse back to the same settings.
        assert_eq!(parse(&pairs).unwrap().pairs(), pairs);
    }

    #[test]
    fn the_observer_is_read_with_displays_flags() {
        let base = defaults();
        assert_eq!(
            (base["age"].as_str(), base["pigmentation"].as_str()),
            ("25", "0.5")
        );
        let (pairs, s) = merge(&base, "age=70&pigmentation=1", &[]).unwrap();
        assert_eq!(
            (pairs["age"].as_str(), pairs["pigmentation"].as_str()),
            ("70", "1")
        );
        let (params, _, _) = s.vision.params(100, Some(40.0)).unwrap();
        assert_eq!(
            (params.observer.age, params.observer.pigmentation),
            (70.0, 1.0)
        );
        assert_eq!(parse(&pairs).unwrap().pairs(), pairs);
    }

    #[test]
    fn bad_settings_are_errors_naming_the_flag() {
        let e = merge(&defaults(), "colour=blue", &[])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("unknown setting 'colour'") && e.contains("scale"),
            "{e}"
        );
        let e = merge(&defaults(), "scale=abc", &[])
            .unwrap_err()
            .to_string();
        assert!(e.contains("--scale"), "{e}");
        let e = merge(&defaults(), "hdr=maybe", &[])
            .unwrap_err()
            .to_string();
        assert!(e.contains("--hdr maybe"), "{e}");
        for scale in ["-1", "1e38", "1e-300", "0"] {
            let (_, s) = merge(&defaults(), &format!("scale={scale}"), &[]).unwrap();
            let e = s.view().unwrap_err().to_string();
            assert!(e.starts_with("--scale "), "{scale}: {e}");
        }
        let (_, s) = merge(&defaults(), "view=sideways", &[]).unwrap();
        assert!(s
            .view()
            .unwrap_err()
            .to_string()
            .contains("--view sideways"));
        for (query, says) in [("age=-3", "--age"), ("pigmentation=1.5", "--pigmentation")] {
            let e = merge(&defaults(), query, &[]).unwrap_err().to_string();
            assert!(e.contains(says), "{query}: {e}");
        }
        // Keys that are not settings are passed over when asked.
        assert!(merge(&defaults(), "x=3&y=4", &["x", "y"]).is_ok());
    }

    #[test]
    fn settings_sent_as_json_are_read_like_a_query() {
        let given =
            from_json(br#"{"scale": 0.02, "glare": false, "tonemap": "exposure"}"#).unwrap();
        let (pairs, s) = merge_pairs(&defaults(), given, &[]).unwrap();
        assert_eq!(s.scale, 0.02);
        assert_eq!(
            (pairs["glare"].as_str(), pairs["tonemap"].as_str()),
            ("off", "exposure")
        );
        for (body, says) in [
            (&b"scale=2"[..], "not JSON"),
            (b"[1]", "not a JSON object"),
            (br#"{"scale": null}"#, "setting 'scale': null"),
            (br#"{"scale": [1]}"#, "setting 'scale'"),
        ] {
            let e = from_json(body).unwrap_err().to_string();
            assert!(e.contains(says), "{e}");
        }
        let e = merge_pairs(
            &defaults(),
            from_json(br#"{"colour": "blue"}"#).unwrap(),
            &[],
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("unknown setting 'colour'"), "{e}");
    }
}
