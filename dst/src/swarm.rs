//! The swarm options of a run (in the manner of VOPR's swarm testing): the seed chooses how
//! many clients there are, which kinds of fault the run suffers and how often, so that the
//! campaign explores both quiet runs and runs where everything goes wrong at once.

use crate::faults::Fault;
use crate::rng::Rng;

/// What a seed chose for its run.
#[derive(Debug, Clone, PartialEq)]
pub struct Swarm {
    pub clients: usize,
    /// Chance per cycle of a new episode of each kind of fault (0: never in this run).
    pub fault_rates: [f64; Fault::ALL.len()],
    /// A [`Driver`](crate::driver::Driver) among the clients (alone when `clients` is 0).
    pub driver: bool,
    /// Faults ten times rarer than drawn: the driver gets further between them.
    pub calm: bool,
}

impl Swarm {
    pub fn draw(rng: &mut Rng) -> Swarm {
        let clients = 1 + rng.below(4) as usize;
        let mut fault_rates = [0.0; Fault::ALL.len()];
        for r in &mut fault_rates {
            if rng.chance(0.5) {
                // About every 5 s, 50 s or 500 s of simulated time.
                *r = rng.pick(&[1.0 / 1_000.0, 1.0 / 10_000.0, 1.0 / 100_000.0]);
            }
        }
        Swarm {
            clients,
            fault_rates,
            driver: false,
            calm: false,
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
        self.calm = rng.chance(0.3);
        if self.calm {
            for r in &mut self.fault_rates {
                *r /= 10.0;
            }
        }
    }

    /// The enabled faults, by name.
    pub fn fault_names(&self) -> Vec<&'static str> {
        Fault::ALL
            .iter()
            .filter(|f| self.fault_rates[f.index()] > 0.0)
            .map(|f| f.name())
            .collect()
    }
}
