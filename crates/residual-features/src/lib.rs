//! Windowing and window features of residual signals (energy, statistics, envelope spectrum)
