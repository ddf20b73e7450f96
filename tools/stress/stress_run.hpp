// Running the stress grid (stress_grid.hpp): the cases on a small thread
// pool, each printed as it ends; a cell's walk stops at its first
// trustworthy run. SIGINT/SIGTERM: runs under way finish, the rest are skipped.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "stress_grid.hpp"

namespace gimbalsim::stress {

/// A scene named by its stem (a file of the scenes folder) or by a path.
std::string scenePath(const std::string& scenes, const std::string& scene);
/// True for a stem: no '/' and no .yaml extension (anything else is a path).
bool isSceneStem(const std::string& scene);

/// Runs job(0 .. n-1) on at most `threads` threads (the caller's included).
void parallel(std::size_t n, int threads, const std::function<void(std::size_t)>& job);

/// One line per case (two with a reason), serialised across threads.
void printCase(const Case& c);

/// Classifies the case with the scene file scenes/<c.scene>.yaml, prints it.
void runCase(Case& c, const std::string& scenes, const Bounds& b);

/// Every case not skipped by a stop request.
void runSweeps(std::vector<Case>& cases, const std::string& scenes, int threads, const Bounds& b);

/// Walks each cell down its grid until the first trustworthy run.
void runGrid(std::vector<Cell>& cells, const std::string& scenes, const std::string& dur, int threads,
             const Bounds& b);

/// The effective restitution table (stress_grid.hpp) for a journal thrown at v_in [m/s].
std::vector<RestitutionRow> restitutionTable(const std::string& scenes, double v_in);

}  // namespace gimbalsim::stress
