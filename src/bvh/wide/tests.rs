//! Wide BVH unit tests.
