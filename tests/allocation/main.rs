//! What loading allocates, counted by a global allocator that sees every byte this process
//! allocates. It is a test binary of its own: any other test running beside it would count too.

mod allocations_follow_file_size;
