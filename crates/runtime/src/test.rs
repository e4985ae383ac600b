//! The test runner (`runtime.md` §5.2): executes a test's statements on a fresh simulation and
//! reports failures, faults and the trace.
