//! The ranks of a distributed run as MPI processes (the `mpi` feature; rsmpi on the system's
//! MPI library, e.g. Debian's Open MPI).

use mpi::environment::Universe;
use mpi::topology::SimpleCommunicator;
use mpi::traits::{Communicator, CommunicatorCollectives, Destination, Source};

use super::Ranks;

/// The processes of `MPI_COMM_WORLD`, with MPI initialised for as long as this lives.
pub struct MpiRanks {
    world: SimpleCommunicator,
    /// The ranks on this machine (`MPI_Comm_split_type` with `MPI_COMM_TYPE_SHARED`).
    on_this_machine: usize,
    /// Finalises MPI when dropped, after `world` (fields drop in order).
    _universe: Universe,
}

impl MpiRanks {
    /// Initialises MPI for this process; `None` when it was already initialised.
    pub fn initialise() -> Option<Self> {
        let universe = mpi::initialize()?;
        let world = universe.world();
        let on_this_machine = usize::try_from(world.split_shared(0).size()).unwrap_or(1);
        Some(Self {
            world,
            on_this_machine,
            _universe: universe,
        })
    }

    /// Ends every rank's process with `code` (`MPI_Abort`): what a rank that cannot go on
    /// does, so that no other rank waits for it forever.
    pub fn abort(&self, code: i32) -> ! {
        self.world.abort(code)
    }
}

impl Ranks for MpiRanks {
    fn rank(&self) -> usize {
        usize::try_from(self.world.rank()).expect("MPI ranks are not negative")
    }

    fn size(&self) -> usize {
        usize::try_from(self.world.size()).expect("MPI sizes are positive")
    }

    fn on_this_machine(&self) -> usize {
        self.on_this_machine
    }

    fn send(&self, to: usize, values: &[f64]) {
        self.world.process_at_rank(mpi_rank(to)).send(values);
    }

    fn receive(&self, from: usize, into: &mut [f64]) {
        self.world
            .process_at_rank(mpi_rank(from))
            .receive_into(into);
    }

    fn exchange(&self, with: usize, values: &[f64], into: &mut [f64]) {
        let other = self.world.process_at_rank(mpi_rank(with));
        mpi::point_to_point::send_receive_into(values, &other, into, &other);
    }

    fn gather_all(&self, value: f64, into: &mut [f64]) {
        self.world.all_gather_into(&value, into);
    }
}

/// A rank as MPI numbers it.
fn mpi_rank(rank: usize) -> i32 {
    i32::try_from(rank).expect("MPI ranks fit an int")
}
