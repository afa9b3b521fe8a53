//! The numerical engine: meshes and finite elements, the discrete model, contact, the time
//! integrators of the 1D paper (§3) and the exact solutions. It knows nothing of runs,
//! studies or files.

pub mod contact;
pub mod distributed;
pub mod error;
pub mod exact;
pub mod fem;
pub mod linalg;
pub mod model;
pub mod problem;
pub mod schemes;
pub mod solver_plan;
