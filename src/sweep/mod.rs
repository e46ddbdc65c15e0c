//! Sweeps: RON sweep files, grid expansion, job ids, the resumable job queue, the rayon runner,
//! Parquet tables and phase diagrams.
