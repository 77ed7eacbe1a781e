//! Scenario files live in `scenarios/`; the tests in `tests/` run them.
