//! The chapter's window energies as the `pipeline` crate's table cells read them: [`Src`], and
//! the dataset of one cell ([`cell_dataset`]).

use super::inputs::{Cache, RecKey};
use super::run::{Config, FeatMap};
use ::pipeline as pl;
use ::pipeline::dissertation::DissTable;

/// A source's window energies and recording ids, as the library's cells read them.
pub struct Src<'a> {
    pub cache: &'a Cache,
    pub feats: &'a FeatMap,
    pub source: &'a str,
}

impl pl::cells::CellSource for Src<'_> {
    fn id(&self, k: &RecKey) -> pl::Result<String> {
        self.cache
            .get(k)
            .map(|r| r.id.clone())
            .map_err(|e| pl::PipelineError::Missing {
                what: e.to_string(),
            })
    }
    fn energies(&self, k: &RecKey) -> pl::Result<&[f64]> {
        self.feats
            .get(&(self.source.to_string(), *k))
            .map(Vec::as_slice)
            .ok_or_else(|| pl::PipelineError::Missing {
                what: format!("window energies of {} on {k:?}", self.source),
            })
    }
}

/// The dataset of one cell (one crack size `ci`, or every size with `ci = None`), classes named
/// by their table labels.
pub fn cell_dataset(
    cfg: &Config,
    cache: &Cache,
    d: &DissTable,
    feats: &FeatMap,
    source: &str,
    ci: Option<usize>,
) -> anyhow::Result<pl::Dataset> {
    let src = Src {
        cache,
        feats,
        source,
    };
    Ok(pl::cells::table_cell_dataset(d, &cfg.scope(), &src, ci)?)
}
