//! Integration tests, one module per area.

mod ortho_cases; // the orthogonal engine: design vectors, oracle, metamorphic
mod ortho_oracle;
mod util; // the orthogonal engine against a brute-force grid oracle
