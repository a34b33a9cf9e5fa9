//! The swarm options of a run (in the manner of VOPR's swarm testing): the seed chooses how
//! many clients there are, which kinds of fault the run suffers and how often, so that the
//! campaign explores both quiet runs and runs where everything goes wrong at once.

use crate::faults::Fault;
use crate::rng::Rng;

/// What a seed chose for its run.
#[derive(Debug, Clone, PartialEq)]
pub struct Swarm {
    pub clients: usize,
    /// Mean time between the episodes of each kind of fault [simulated s] (`None`: never in
    /// this run).
    pub fault_every_s: [Option<f64>; Fault::ALL.len()],
    /// A [`Driver`](crate::driver::Driver) among the clients (alone when `clients` is 0).
    pub driver: bool,
}

impl Swarm {
    /// The options of a run whose faults are of the first `kinds` of [`Fault::ALL`] (a finding
    /// keeps the count it was found with: each kind added later draws a chance, and so changes
    /// every draw after it).
    pub fn draw(rng: &mut Rng, kinds: usize) -> Swarm {
        let clients = 1 + rng.below(4) as usize;
        let mut fault_every_s = [None; Fault::ALL.len()];
        for every in fault_every_s.iter_mut().take(kinds) {
            if rng.chance(0.5) {
                *every = Some(rng.pick(&[5.0, 50.0, 500.0]));
            }
        }
        Swarm {
            clients,
            fault_every_s,
            driver: false,
        }
    }

    /// The roles (drawn after the rest, from their own generator, so that a seed's clients,
    /// faults and configuration stay what they were without them).
    pub fn draw_roles(&mut self, rng: &mut Rng) {
        self.driver = rng.chance(0.5);
        // Half the drivers drive alone: any client's `hold` aborts a calibration of all axes,
        // which takes tens of seconds, so that with others around it rarely ends.
        if self.driver && rng.chance(0.5) {
            self.clients = 0;
        }
        // A calm run: faults ten times rarer than drawn, so that the driver gets further
        // between them.
        if rng.chance(0.3) {
            for every in self.fault_every_s.iter_mut().flatten() {
                *every *= 10.0;
            }
        }
    }

    /// The enabled faults, by name.
    pub fn fault_names(&self) -> Vec<&'static str> {
        Fault::ALL
            .iter()
            .filter(|f| self.fault_every_s[f.index()].is_some())
            .map(|f| f.name())
            .collect()
    }
}
