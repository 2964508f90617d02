//! CWRU bearing recordings: embedded catalog, MAT/CSV readers, checksums, decimation
