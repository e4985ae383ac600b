//! Chart properties and the chart's sequencers as a whole: HG7402 (unknown `run` option),
//! HG7403 (repeated property), HG7406 (`switching` not offered in `mode auto`), HG7208 (no
//! sequencer), HG7206 (too many sequencers), HG7207 (sequencer priority) and HG7105 (duplicate
//! sequencer names).

use higraph_syntax::{
    SyntaxKind, TextRange,
    ast::{self, AstNode},
};

use super::{ChartInfo, has_error, header_range, without_semi};
use crate::rules::Ctx;

/// The `run` options a chart knows (HG7402).
const RUN_OPTIONS: [&str; 3] = ["cyclic", "time_monitoring", "autostart"];

/// The chart properties that other rules need.
pub(crate) struct ChartProps {
    /// The first `switching` value as written; `None` means the default `T`.
    pub switching: Option<String>,
    /// `run time_monitoring;` is set (HG7404).
    pub time_monitoring: bool,
    /// `profile iec;` (`docs/iec.md`).
    pub iec: bool,
}

/// One property as written.
struct Prop {
    /// `mode`, `switching` or `run {option}` (lower case keyword): what HG7403 compares.
    key: String,
    /// What HG7403 calls it: `mode`, `switching`, `run cyclic`.
    display: String,
    value: String,
    /// The property without its `;`.
    range: TextRange,
    /// The whole property, for removal.
    node: TextRange,
}

/// Checks the properties (HG7402, HG7403, HG7406) and returns what other rules need.
pub(crate) fn check_props(ctx: &mut Ctx<'_>, info: &ChartInfo) -> ChartProps {
    let mut seen: Vec<Prop> = Vec::new();
    for prop in info.chart.props() {
        let Some(prop) = read_prop(ctx, &prop) else {
            continue;
        };
        match seen.iter().find(|p| p.key == prop.key) {
            Some(first) => report_repeated(ctx, &prop, first),
            None => seen.push(prop),
        }
    }
    let first = |key: &str| seen.iter().find(|p| p.key == key);
    if let (Some(mode), Some(switching)) = (first("mode"), first("switching"))
        && mode.value.eq_ignore_ascii_case("auto")
        && ["B", "T_and_B", "T_or_B"]
            .iter()
            .any(|m| m.eq_ignore_ascii_case(&switching.value))
    {
        let diag = ctx.diag(
            "HG7406",
            switching.range,
            format!(
                "switching mode {} is not available in operating mode auto (only T and step)",
                switching.value
            ),
        );
        ctx.push(diag);
    }
    ChartProps {
        switching: first("switching").map(|p| p.value.clone()),
        time_monitoring: first("run time_monitoring").is_some(),
        iec: info.is_iec(),
    }
}

/// Reads one property; HG7402 for an unknown `run` option. Broken properties are skipped (C1).
fn read_prop(ctx: &mut Ctx<'_>, prop: &ast::ChartProp) -> Option<Prop> {
    if has_error(prop.syntax()) {
        return None;
    }
    let keyword = prop.keyword()?;
    let value = prop.value()?;
    let value_token = value.token()?;
    let value_text = value_token.text().to_owned();
    let (key, display) = match keyword.kind() {
        SyntaxKind::MODE_KW => ("mode".to_owned(), "mode".to_owned()),
        SyntaxKind::SWITCHING_KW => ("switching".to_owned(), "switching".to_owned()),
        SyntaxKind::RUN_KW => {
            check_run_option(ctx, &value_text, value_token.text_range());
            (
                format!("run {}", value_text.to_ascii_lowercase()),
                format!("run {value_text}"),
            )
        }
        SyntaxKind::PROFILE_KW => {
            check_profile(ctx, &value_text, value_token.text_range());
            ("profile".to_owned(), "profile".to_owned())
        }
        _ => return None,
    };
    Some(Prop {
        key,
        display,
        value: value_text,
        range: without_semi(prop.syntax()),
        node: prop.syntax().text_range(),
    })
}

/// HG7402: `run` takes only `cyclic`, `time_monitoring` and `autostart`.
fn check_run_option(ctx: &mut Ctx<'_>, option: &str, range: TextRange) {
    if RUN_OPTIONS.iter().any(|o| o.eq_ignore_ascii_case(option)) {
        return;
    }
    let mut diag = ctx.diag(
        "HG7402",
        range,
        format!("unknown run option '{option}'; known: cyclic, time_monitoring, autostart"),
    );
    diag = ctx.with_closest_fix(diag, range, option, RUN_OPTIONS);
    ctx.push(diag);
}

/// HG7501: `profile` takes only `pcs7` and `iec`.
fn check_profile(ctx: &mut Ctx<'_>, profile: &str, range: TextRange) {
    const PROFILES: [&str; 2] = ["pcs7", "iec"];
    if PROFILES.iter().any(|p| p.eq_ignore_ascii_case(profile)) {
        return;
    }
    let diag = ctx.diag(
        "HG7501",
        range,
        format!("unknown profile '{profile}'; known: pcs7, iec"),
    );
    let diag = ctx.with_closest_fix(diag, range, profile, PROFILES);
    ctx.push(diag);
}

/// HG7403: the later of two equal properties; the first one applies.
fn report_repeated(ctx: &mut Ctx<'_>, prop: &Prop, first: &Prop) {
    let diag = ctx
        .diag(
            "HG7403",
            prop.range,
            format!(
                "chart property '{}' is given twice; the first one applies",
                prop.display
            ),
        )
        .related(
            ctx.loc(first.range),
            format!("the first '{}'", first.display),
        )
        .fix(
            format!("Remove the second '{}'", prop.display),
            ctx.loc(prop.node),
            "",
        );
    ctx.push(diag);
}

/// HG7208, HG7206, HG7207 and HG7105 over the chart's sequencers.
pub(crate) fn check_sequencers(ctx: &mut Ctx<'_>, info: &ChartInfo) {
    let sequencers: Vec<ast::Sequencer> = info.chart.sequencers().collect();
    if sequencers.is_empty() {
        if let Some(token) = info.chart.name().and_then(|n| n.token()) {
            let diag = ctx.diag(
                "HG7208",
                token.text_range(),
                format!("chart {} has no sequencer", info.name),
            );
            ctx.push(diag);
        }
        return;
    }
    let iec = info.is_iec();
    if iec {
        iec_sequencers(ctx, &sequencers);
    } else {
        check_sequencer_limit(ctx, info, &sequencers);
    }
    let mut names: Vec<(String, TextRange)> = Vec::new();
    for sequencer in &sequencers {
        if !iec {
            check_prio(ctx, sequencer);
        }
        let Some(token) = sequencer.name().and_then(|n| n.token()) else {
            continue;
        };
        let name = token.text().to_owned();
        if let Some((first, first_range)) =
            names.iter().find(|(n, _)| n.eq_ignore_ascii_case(&name))
        {
            let diag = ctx
                .diag(
                    "HG7105",
                    token.text_range(),
                    format!(
                        "sequencer name '{name}' is already used in chart {}",
                        info.name
                    ),
                )
                .related(
                    ctx.loc(*first_range),
                    format!("first sequencer named '{first}'"),
                );
            ctx.push(diag);
        } else {
            names.push((name, token.text_range()));
        }
    }
}

/// HG7503: an IEC chart has one sequencer, without `start` and `prio`.
fn iec_sequencers(ctx: &mut Ctx<'_>, sequencers: &[ast::Sequencer]) {
    for (i, sequencer) in sequencers.iter().enumerate() {
        let name = sequencer.name().map(|n| n.text()).unwrap_or_default();
        if i > 0 {
            let diag = ctx
                .diag(
                    "HG7503",
                    header_range(sequencer.syntax()),
                    format!(
                        "an IEC chart has one sequencer without 'start' and 'prio'; {name} is a second sequencer"
                    ),
                )
                .related(
                    ctx.loc(header_range(sequencers[0].syntax())),
                    "the chart's sequencer",
                );
            ctx.push(diag);
            continue;
        }
        if let Some(prio) = sequencer.prio() {
            let diag = ctx.diag(
                "HG7503",
                prio.syntax().text_range(),
                format!(
                    "an IEC chart has one sequencer without 'start' and 'prio'; remove the priority of {name}"
                ),
            );
            let diag = diag.fix(
                "Remove the priority",
                ctx.loc(prio.syntax().text_range()),
                "",
            );
            ctx.push(diag);
        }
        let starts = sequencer
            .body()
            .into_iter()
            .flat_map(|b| b.syntax().children().collect::<Vec<_>>())
            .filter(|n| n.kind() == SyntaxKind::START_PART);
        for start in starts {
            let range = super::first_token(&start).map_or(start.text_range(), |t| t.text_range());
            let diag = ctx.diag(
                "HG7503",
                range,
                format!(
                    "an IEC chart has one sequencer without 'start' and 'prio'; {name} runs from the chart's first cycle, so it has no start condition"
                ),
            );
            ctx.push(diag);
        }
    }
}

/// HG7206: at most 8 sequencers in a chart, 32 in a chart type (C5: reported once).
fn check_sequencer_limit(ctx: &mut Ctx<'_>, info: &ChartInfo, sequencers: &[ast::Sequencer]) {
    let limit = if info.is_type { 32 } else { 8 };
    // C5: sequencers whose header parsed (they have a name).
    let counted: Vec<&ast::Sequencer> = sequencers.iter().filter(|s| s.name().is_some()).collect();
    if let Some(beyond) = counted.get(limit) {
        let diag = ctx.diag(
            "HG7206",
            header_range(beyond.syntax()),
            format!(
                "chart {} has {} sequencers; at most {limit} are allowed",
                info.name,
                counted.len()
            ),
        );
        ctx.push(diag);
    }
}

/// HG7207: a sequencer `prio` outside 1..32.
fn check_prio(ctx: &mut Ctx<'_>, sequencer: &ast::Sequencer) {
    let Some(prio) = sequencer.prio() else {
        return;
    };
    let Some(value) = prio.value() else {
        return;
    };
    let in_range = value
        .text()
        .parse::<u64>()
        .is_ok_and(|p| (1..=32).contains(&p));
    if !in_range {
        let diag = ctx.diag(
            "HG7207",
            prio.syntax().text_range(),
            format!("sequencer priority {} is outside 1..32", value.text()),
        );
        ctx.push(diag);
    }
}
