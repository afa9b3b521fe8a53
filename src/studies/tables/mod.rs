//! The 1D paper's Tables 1–2 recomputed (`make report`): the paper's values ([`paper`]) and
//! the agreement of a study with them ([`agreement`]).

pub mod agreement;
pub mod paper;
