// `lagrangian-mpi`: the `sweep` command over MPI ranks (docs/sweeps.md).
//
//   mpirun -np K lagrangian-mpi sweep SCENE --vary ... [--threads T]
//
// Rank r runs the points i with i mod K = r (with T threads); rank 0
// gathers every rank's results (MPI_Gatherv of their serialized rows) and
// alone writes sweep.csv and the plots. Exit codes as `lagrangian sweep`.

#include <mpi.h>

#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "subcommands.hpp"
#include "sweep_command.hpp"

namespace {

bool reached_gather = false;

/// Whether every rank reached the gather: each rank says whether it did
/// (`ok`); returns the first rank that did not, or -1. A rank that stopped
/// early (a scene file missing on its node, an output directory rank 0
/// cannot create) calls this instead of the gather, so that no rank waits
/// for it forever.
int first_failed_rank(bool ok) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const int mine = ok ? 1 : 0;
  std::vector<int> all(static_cast<std::size_t>(size));
  MPI_Allgather(&mine, 1, MPI_INT, all.data(), 1, MPI_INT, MPI_COMM_WORLD);
  for (int r = 0; r < size; ++r)
    if (all[static_cast<std::size_t>(r)] == 0) return r;
  return -1;
}

/// Every rank's text, concatenated in rank order, on rank 0 (empty elsewhere).
std::string gather_to_root(const std::string& mine) {
  reached_gather = true;
  if (const int failed = first_failed_rank(true); failed >= 0)
    throw std::runtime_error("rank " + std::to_string(failed) + " stopped before the results were gathered");
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const int length = static_cast<int>(mine.size());
  std::vector<int> lengths(static_cast<std::size_t>(size)), offsets(static_cast<std::size_t>(size));
  MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::string all;
  if (rank == 0) {
    long long total = 0;
    for (int r = 0; r < size; ++r) {
      offsets[static_cast<std::size_t>(r)] = static_cast<int>(total);
      total += lengths[static_cast<std::size_t>(r)];
    }
    all.resize(static_cast<std::size_t>(total));
  }
  MPI_Gatherv(mine.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR, 0,
              MPI_COMM_WORLD);
  return all;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);

  CLI::App app{"lagrangian-mpi: the sweep command of lagrangian over MPI ranks (run it under mpirun -np K).\n"
               "Exit codes: 0 ok, 1 some runs failed, 2 bad input."};
  app.require_subcommand(1);
  lagrangian::cli::SweepCommand sweep;
  sweep.add(app);
  int code = 0;
  if (const auto word = lagrangian::cli::unknown_subcommand(app, argc, argv)) {
    // The same command line on every rank: only rank 0 speaks.
    if (rank == 0)
      std::cerr << "lagrangian-mpi: " << lagrangian::cli::unknown_subcommand_message(app, *word)
                << "; lagrangian-mpi runs sweeps only (mpirun -np K lagrangian-mpi sweep SCENE ...), and "
                   "`lagrangian run` runs a single scene\n";
    MPI_Finalize();
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // The same command line on every rank: all stop here, only rank 0 speaks.
    code = rank == 0 ? app.exit(e) : e.get_exit_code();
    MPI_Finalize();
    return code == 0 ? 0 : 2;
  }
  code = sweep.run(rank, size, &gather_to_root);
  if (!reached_gather && size > 1) {
    // This rank stopped before the gather. When rank 0 stopped too (bad
    // input stops every rank alike) rank 0 has said why; otherwise this rank
    // says which it is and why.
    const int failed = first_failed_rank(false);
    if (failed != 0) std::cerr << "lagrangian-mpi: rank " << rank << ": " << sweep.error() << "\n";
  }
  // One exit code for all ranks (mpirun reports the first to exit): the
  // worst — 2 bad input over 1 failed over 0.
  int worst = code;
  MPI_Allreduce(&code, &worst, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return worst;
}
