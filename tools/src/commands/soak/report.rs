//! What a soak measured, the bars of issue #13 it is judged by, and how it is printed.

use super::edits::EditCounts;
use serde::Serialize;

/// Largest growth of this process's RSS from the baseline (after the first minute) to the end
/// [MB] (#13).
pub const RSS_GROWTH_BAR_MB: f64 = 5.0;

/// One agent's counters at the end.
#[derive(Debug, Clone, Serialize)]
pub struct AgentFigures {
    pub team: String,
    pub unum: u32,
    /// Successful connections, the first included: 1 in a healthy soak.
    pub connections: u64,
    pub missed_cycles: u64,
    pub unreadable: u64,
    pub percepts: u64,
    /// The agent still answered percepts when play ended.
    pub answering_at_end: bool,
    /// Its thread ended in a panic.
    pub panicked: bool,
}

/// Everything the soak reports.
#[derive(Debug, Clone, Serialize)]
pub struct SoakReport {
    pub planned_play_s: f64,
    pub play_time_s: f64,
    pub wall_time_s: f64,
    /// How play ended: `"full"` when the planned time was played, else why not.
    pub ended: String,
    pub edit_every_s: f64,
    pub edits: EditCounts,
    /// Play time at which the baseline RSS was read [s].
    pub rss_baseline_at_s: f64,
    pub rss_baseline_mb: Option<f64>,
    pub rss_end_mb: f64,
    pub rss_growth_mb: Option<f64>,
    pub rss_peak_mb: f64,
    /// RSS after each minute of play [MB].
    pub rss_by_minute_mb: Vec<f64>,
    pub agents: Vec<AgentFigures>,
    pub missed_cycles: u64,
    pub unreadable: u64,
    /// Bars that failed, each named; empty when the soak passed.
    pub failures: Vec<String>,
    pub passed: bool,
}

impl SoakReport {
    /// Judge the figures against the bars; fills `failures` and `passed`.
    pub fn judge(&mut self) {
        let mut failures = Vec::new();
        if self.play_time_s + 0.05 < self.planned_play_s {
            failures.push(format!(
                "play time {:.1} s of {:.1} planned ({})",
                self.play_time_s, self.planned_play_s, self.ended
            ));
        }
        match self.rss_growth_mb {
            Some(growth) if growth > RSS_GROWTH_BAR_MB => failures.push(format!(
                "RSS grew {growth:.1} MB (bar {RSS_GROWTH_BAR_MB} MB)"
            )),
            Some(_) => {}
            None => failures.push("no RSS baseline (play ended before it was read)".into()),
        }
        let named = |pred: &dyn Fn(&AgentFigures) -> bool| -> Vec<String> {
            self.agents
                .iter()
                .filter(|a| pred(a))
                .map(|a| format!("{} {}", a.team, a.unum))
                .collect()
        };
        let list = |what: &str, agents: Vec<String>| -> Option<String> {
            (!agents.is_empty()).then(|| format!("{what}: {}", agents.join(", ")))
        };
        failures.extend(list("panicked", named(&|a| a.panicked)));
        failures.extend(list(
            "not connected exactly once",
            named(&|a| a.connections != 1),
        ));
        failures.extend(list(
            "not answering at the end",
            named(&|a| !a.answering_at_end),
        ));
        if self.missed_cycles > 0 {
            failures.push(format!("{} missed cycles", self.missed_cycles));
        }
        let e = &self.edits;
        for (done, of, what) in [
            (e.good_taken, e.good_written, "good edits taken"),
            (e.broken_refused, e.broken_written, "broken edits refused"),
            (
                e.played_on_after_broken,
                e.broken_refused,
                "refused edits after which the team played on",
            ),
            (e.restores_taken, e.restores_written, "restores taken"),
        ] {
            if done < of {
                failures.push(format!("{what} {done} of {of}"));
            }
        }
        self.passed = failures.is_empty();
        self.failures = failures;
    }

    /// One figure per line.
    pub fn text(&self) -> String {
        let mb = |v: Option<f64>| v.map_or_else(|| "—".into(), |v| format!("{v:.1} MB"));
        let e = &self.edits;
        let mut lines = vec![
            format!(
                "play time: {:.1} s of {:.1} planned ({})",
                self.play_time_s, self.planned_play_s, self.ended
            ),
            format!(
                "wall time: {:.1} s ({:.2}× real time)",
                self.wall_time_s,
                self.play_time_s / self.wall_time_s.max(1e-9)
            ),
            format!(
                "good edits: {} written, {} taken",
                e.good_written, e.good_taken
            ),
            format!(
                "broken edits: {} written, {} refused, the team played on after {}",
                e.broken_written, e.broken_refused, e.played_on_after_broken
            ),
            format!(
                "restores: {} written, {} taken",
                e.restores_written, e.restores_taken
            ),
            format!(
                "RSS after {:.0} s of play: {}",
                self.rss_baseline_at_s,
                mb(self.rss_baseline_mb)
            ),
            format!("RSS at the end: {:.1} MB", self.rss_end_mb),
            format!(
                "RSS growth: {} (bar {RSS_GROWTH_BAR_MB} MB)",
                self.rss_growth_mb
                    .map_or_else(|| "—".into(), |g| format!("{g:+.1} MB"))
            ),
            format!("RSS peak: {:.1} MB", self.rss_peak_mb),
            format!(
                "RSS by minute: {}",
                self.rss_by_minute_mb
                    .iter()
                    .map(|v| format!("{v:.1}"))
                    .collect::<Vec<_>>()
                    .join(" ")
            ),
        ];
        let per_team = |figure: &dyn Fn(&AgentFigures) -> String| -> String {
            let mut teams: Vec<&str> = self.agents.iter().map(|a| a.team.as_str()).collect();
            teams.dedup();
            teams
                .iter()
                .map(|team| {
                    let values: Vec<String> = self
                        .agents
                        .iter()
                        .filter(|a| a.team == *team)
                        .map(figure)
                        .collect();
                    format!("{team} {}", values.join(" "))
                })
                .collect::<Vec<_>>()
                .join(", ")
        };
        lines.push(format!(
            "connections per agent: {}",
            per_team(&|a| a.connections.to_string())
        ));
        lines.push(format!(
            "missed cycles: {} ({})",
            self.missed_cycles,
            per_team(&|a| a.missed_cycles.to_string())
        ));
        lines.push(format!("unreadable percepts: {}", self.unreadable));
        let panicked: Vec<String> = self
            .agents
            .iter()
            .filter(|a| a.panicked)
            .map(|a| format!("{} {}", a.team, a.unum))
            .collect();
        lines.push(format!(
            "agent panics: {}",
            if panicked.is_empty() {
                "none".into()
            } else {
                panicked.join(", ")
            }
        ));
        lines.push(if self.passed {
            "result: PASS".into()
        } else {
            format!("result: FAIL — {}", self.failures.join("; "))
        });
        lines.join("\n")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn healthy() -> SoakReport {
        let agent = |team: &str, unum| AgentFigures {
            team: team.into(),
            unum,
            connections: 1,
            missed_cycles: 0,
            unreadable: 0,
            percepts: 3000,
            answering_at_end: true,
            panicked: false,
        };
        SoakReport {
            planned_play_s: 60.0,
            play_time_s: 60.02,
            wall_time_s: 40.0,
            ended: "full".into(),
            edit_every_s: 5.0,
            edits: EditCounts {
                good_written: 6,
                good_taken: 6,
                broken_written: 5,
                broken_refused: 5,
                played_on_after_broken: 5,
                restores_written: 11,
                restores_taken: 11,
            },
            rss_baseline_at_s: 20.0,
            rss_baseline_mb: Some(100.0),
            rss_end_mb: 101.0,
            rss_growth_mb: Some(1.0),
            rss_peak_mb: 110.0,
            rss_by_minute_mb: vec![101.0],
            agents: vec![agent("Libero", 1), agent("Libero", 2), agent("Standing", 1)],
            missed_cycles: 0,
            unreadable: 0,
            failures: Vec::new(),
            passed: false,
        }
    }

    #[test]
    fn a_healthy_soak_passes_and_prints_every_figure() {
        let mut report = healthy();
        report.judge();
        assert!(report.passed, "{:?}", report.failures);
        let text = report.text();
        for line in [
            "play time: 60.0 s of 60.0 planned (full)",
            "good edits: 6 written, 6 taken",
            "broken edits: 5 written, 5 refused, the team played on after 5",
            "RSS growth: +1.0 MB",
            "connections per agent: Libero 1 1, Standing 1",
            "missed cycles: 0 (Libero 0 0, Standing 0)",
            "agent panics: none",
            "result: PASS",
        ] {
            assert!(text.contains(line), "missing `{line}` in:\n{text}");
        }
    }

    #[test]
    fn each_bar_fails_on_its_own_and_is_named() {
        type Break = fn(&mut SoakReport);
        let cases: [(Break, &str); 9] = [
            (|r| r.rss_growth_mb = Some(5.5), "RSS grew 5.5 MB"),
            (|r| r.rss_growth_mb = None, "no RSS baseline"),
            (
                |r| r.agents[1].connections = 2,
                "not connected exactly once: Libero 2",
            ),
            (|r| r.agents[2].panicked = true, "panicked: Standing 1"),
            (
                |r| r.agents[0].answering_at_end = false,
                "not answering at the end: Libero 1",
            ),
            (|r| r.missed_cycles = 3, "3 missed cycles"),
            (|r| r.edits.good_taken = 5, "good edits taken 5 of 6"),
            (
                |r| r.edits.broken_refused = 4,
                "broken edits refused 4 of 5",
            ),
            (|r| r.play_time_s = 30.0, "play time 30.0 s of 60.0 planned"),
        ];
        for (spoil, expected) in cases {
            let mut report = healthy();
            spoil(&mut report);
            report.judge();
            assert!(!report.passed, "{expected}: passed");
            assert_eq!(report.failures.len(), 1, "{:?}", report.failures);
            assert!(
                report.failures[0].contains(expected),
                "{expected}: {:?}",
                report.failures
            );
            assert!(report.text().contains("result: FAIL"), "{}", report.text());
        }
    }
}
