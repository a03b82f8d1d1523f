//! The integration tests of `dyngen-codegen`: one module per subject, in one test binary
//! (one link instead of one per file, one pool of test threads). A test that changes
//! process-wide state goes in a file of its own beside this directory.

mod base_parameters;
mod build_script_api;
mod builder_output_file;
mod constrained_oracles;
mod constrained_reference;
mod contact_descriptions;
mod derivative_stages;
mod description_errors;
mod descriptions;
mod emitted_code;
mod energy;
mod example_robot_data;
mod factored_transforms;
mod floating_base_parameters;
mod floating_descriptions;
mod floating_oracles;
mod floating_reference;
mod forward_dynamics_accuracy;
mod forward_dynamics_joint_terms;
mod forward_dynamics_random_trees;
mod frame_descriptions;
mod frame_oracles;
mod frame_reference;
mod function_groups;
mod fuzz;
mod joint_terms;
mod mimic_oracles;
mod mimic_reference;
mod module_layers;
mod near_exact_angles;
mod no_data_loss;
mod non_physical_inertia;
mod oracles;
mod quantity_table;
mod reference_fixtures;
mod reference_forward_dynamics;
mod regressor_forms;
mod regressor_products;
mod result_fills;
mod scale;
mod singular_inertia;
mod symbolic_interpreter;
mod urdf_rs_interop;
mod warnings_reported;
