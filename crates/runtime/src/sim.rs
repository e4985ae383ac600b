//! A simulation: a machine, the groups' and charts' run-time state, the clock; one machine
//! cycle at a time (`runtime.md` §1.3).
