// `lagrangian-mpi`: the `sweep` command over MPI ranks (docs/sweeps.md).
//
//   mpirun -np K lagrangian-mpi sweep SCENE --vary ... [--threads T]
//
// Rank r runs the points i with i mod K = r (with T threads); rank 0
// gathers every rank's results (MPI_Gatherv of their serialized rows) and
// alone writes sweep.csv and the plots. Exit codes as `lagrangian sweep`.

#include <mpi.h>

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "sweep_command.hpp"

namespace {

/// Every rank's text, concatenated in rank order, on rank 0 (empty elsewhere).
std::string gather_to_root(const std::string& mine) {
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
  try {
    app.parse(argc, argv);
    code = sweep.run(rank, size, &gather_to_root);
  } catch (const CLI::ParseError& e) {
    code = rank == 0 ? app.exit(e) : (e.get_exit_code() == 0 ? 0 : 2);
    if (code != 0) code = 2;
  }
  // Every rank reaches here (bad input is found alike on every rank, before
  // any collective call), so the ranks agree on the exit code.
  MPI_Finalize();
  return code;
}
