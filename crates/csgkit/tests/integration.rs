//! Integration tests, one module per area.

mod ortho_cases; // the orthogonal engine: design vectors, oracle, metamorphic
mod ortho_oracle;
mod ortho_vox;
mod util; // the orthogonal engine against a brute-force grid oracle // the orthogonal engine on the shared MagicaVoxel models
