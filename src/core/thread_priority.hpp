// Background threads yield to the one drawing frames: a thread lowers its own scheduling priority
// (a larger nice value, Linux threads having their own), and threads it starts afterwards inherit it.
#pragma once

namespace lidarscout {

// Makes the calling thread `steps` nicer than the process (0: unchanged); quietly does nothing where
// the system refuses (a priority is a hint, not a correctness matter).
void lower_thread_priority(int steps);

}  // namespace lidarscout
