//! Low-level skills: beam, stand, look, walk, kick, get up; each turns an intent into joint targets.
