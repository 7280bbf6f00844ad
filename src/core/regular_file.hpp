// Local inputs are read only when they are regular files. A FIFO named by a catalog item, a tile
// list or an argument would hang the read (opening one for reading waits for a writer, and a read
// then waits for data), a device or a socket never ends or fails in odd ways, and a folder is not
// a file. So a file is checked before it is read: by stat before a stream opens it, or on a
// descriptor opened without blocking (O_NONBLOCK), which then blocks as usual again.
#pragma once

#include <string>
#include <sys/types.h>

namespace lidarscout {

// What a stat mode that is not a regular file's names ("a FIFO", "a folder", "a character
// device", ...); "" for a regular file.
std::string non_regular_kind(mode_t mode);

// Throws Error (naming `path`: "is a FIFO, not a regular file") when `path` exists and is not a
// regular file; nothing when it is one or does not exist (opening it then says why).
void require_regular_file(const std::string& path);

// ::open(path, O_RDONLY | O_CLOEXEC | flags) that never blocks on a FIFO: -1 with errno set when
// the open fails; throws Error as require_regular_file does when what it opened is not a regular
// file (the descriptor closed). The descriptor returned blocks as usual.
int open_regular_file(const std::string& path, int flags = 0);

}  // namespace lidarscout
