//! World state: self, ball, players and game state estimated from percepts.
