// Plans for a farm (docs/farm.md): a folder holding tasks.txt, one complete `penumbra` command
// per line (task i is line i + 1, so a job array's index picks its line), finish.txt, the
// commands to run once every task succeeded (a merge or a collect), and plan.json describing
// both. Commands use absolute paths, so any node that shares the file system can run them.
#pragma once

#include <string>
#include <vector>

namespace penumbra {

// The command line as typed, one element per argument (argv[1...]).
std::vector<std::string>& commandArguments();

// The running executable's absolute path (for the tasks' commands).
std::string executablePath();

// `arg` quoted for a POSIX shell when it needs to be.
std::string shellQuote(const std::string& arg);

// The typed arguments without the options in `drop` (each with its value; both "--x v" and
// "--x=v" forms) and flags in `dropFlags`, with `scenePath` made absolute.
std::vector<std::string> argumentsWithout(const std::vector<std::string>& drop,
                                          const std::vector<std::string>& dropFlags,
                                          const std::string& scenePath);

// Writes DIR/tasks.txt, DIR/finish.txt and DIR/plan.json (atomically, each), creating DIR.
// Throws CommandError when DIR cannot be written.
void writePlan(const std::string& dir, const std::string& kind,
               const std::vector<std::string>& tasks, const std::vector<std::string>& finish);

}  // namespace penumbra
