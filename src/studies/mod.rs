//! The studies behind the report's sections: the paper's tables, gravity, the extended
//! table, stability, cost, the 2D/3D elastic study, and the figures drawn from their files.

pub mod cost;
pub mod elastic_study;
pub mod extended;
pub mod figures;
pub mod pipeline;
pub mod stability;
pub mod tables;
