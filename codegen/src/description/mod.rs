//! Robot descriptions (URDF, YAML) → Model. (being written)
