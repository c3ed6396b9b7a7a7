//! Host harness for curvicast (placeholder, being built).
