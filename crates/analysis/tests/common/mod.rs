//! What the analysis' integration tests share: the workspace format of the rule fixtures
//! (`higraph_analysis::fixture_workspace`), and the sources of a fixture.

// Each test binary uses its own part of this module.
#![allow(dead_code, unused_imports)]

pub use higraph_analysis::fixture_workspace::{FixtureFile, fixture_files, load_fixture};

/// The `.higraph` texts of a fixture (lossily decoded), in fixture order.
pub fn fixture_sources(bytes: &[u8]) -> Vec<String> {
    fixture_files(bytes)
        .into_iter()
        .filter(|(path, _)| path.ends_with(".higraph"))
        .map(|(_, body)| String::from_utf8_lossy(&body).into_owned())
        .collect()
}
