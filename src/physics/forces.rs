//! Force evaluation over the flat element arrays.
