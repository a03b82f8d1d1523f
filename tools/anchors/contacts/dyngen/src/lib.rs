//! The Unitree G1 with both feet held as frames (`g1.yaml`), generated at build time: the dyngen
//! side of the G1's rows in `tools/compare_contacts.py` (`benches/contacts.rs`).

dyngen_runtime::include_robot!(g1);
