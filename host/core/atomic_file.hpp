// Atomic file writing: the one place that writes a file so that a reader (another process, a batch
// resumed after a crash) sees either the old file or the whole new one, never a half-written one.
// The content goes to a hidden temporary file in the same folder ('.<name>.tmp<pid>[suffix]'), which is
// renamed over the target when complete (rename(2) within one file system is atomic, POSIX.1-2017).
#pragma once
#include <cstddef>
#include <functional>
#include <string>

namespace shadelab {

// Fills the temporary file at `tmp_path`. Returns false when writing failed, with the reason in `why`
// when one is known (it may stay empty). It may also throw; the temporary file is removed either way.
using FillFile = std::function<bool(const std::string& tmp_path, std::string& why)>;

// Writes `path` atomically: creates its folder when missing, calls `fill` on a temporary file next to it,
// then renames that over `path`. `what` names the content in the error messages ("image", "table",
// "report"); `tmp_suffix` ends the temporary file's name (e.g. ".png", for writers that choose the format
// from the extension). Throws Error with one line naming the file and what to do; leaves no temporary.
void write_file_atomically(const std::string& path, const std::string& what, const FillFile& fill,
                           const std::string& tmp_suffix = "");

// The same for content already in memory (text or bytes, written as they are).
void write_text_atomically(const std::string& path, const std::string& what, const std::string& bytes);

// A process killed while writing (kill -9, power off) leaves its '.<name>.tmp<pid>[suffix]' behind. Removes
// such files directly in `folder` whose process no longer exists (a live process's are left alone, so
// two runs writing into one folder do not harm each other). Returns how many were removed; a missing
// folder is 0.
std::size_t remove_stale_temporaries(const std::string& folder);

}  // namespace shadelab
