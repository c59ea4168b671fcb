//! Integration tests, one module per area.

mod util;

// The orthogonal engine: design vectors E1-E10 and R1-R6.
mod ortho_cases;
// The orthogonal engine against a brute-force grid oracle; metamorphic relations.
mod ortho_oracle;
// The orthogonal engine on the shared MagicaVoxel models.
mod ortho_vox;
