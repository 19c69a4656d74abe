// Owning handles for SUNDIALS objects (context, vectors, matrices, solvers, solver memory).
#pragma once

#include <memory>
#include <type_traits>

#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nonlinearsolver.h>
#include <sundials/sundials_nvector.h>

namespace mbstream::sundials {

// Which SUNDIALS package a solver memory block belongs to.
enum class Family { kCvode, kArkode };

struct ContextDeleter {
  void operator()(SUNContext context) const { SUNContext_Free(&context); }
};
struct VectorDeleter {
  void operator()(N_Vector vector) const { N_VDestroy(vector); }
};
struct MatrixDeleter {
  void operator()(SUNMatrix matrix) const { SUNMatDestroy(matrix); }
};
struct LinearSolverDeleter {
  void operator()(SUNLinearSolver solver) const { SUNLinSolFree(solver); }
};
struct NonlinearSolverDeleter {
  void operator()(SUNNonlinearSolver solver) const { SUNNonlinSolFree(solver); }
};

using Context = std::unique_ptr<std::remove_pointer_t<SUNContext>, ContextDeleter>;
using Vector = std::unique_ptr<std::remove_pointer_t<N_Vector>, VectorDeleter>;
using Matrix = std::unique_ptr<std::remove_pointer_t<SUNMatrix>, MatrixDeleter>;
using LinearSolver = std::unique_ptr<std::remove_pointer_t<SUNLinearSolver>, LinearSolverDeleter>;
using NonlinearSolver =
    std::unique_ptr<std::remove_pointer_t<SUNNonlinearSolver>, NonlinearSolverDeleter>;

// The memory block of CVODE or ARKStep, freed with its own function
// (CVodeFree, ARKStepFree).
class SolverMemory {
 public:
  using FreeFunction = void (*)(void**);
  SolverMemory(void* memory, FreeFunction free_function) : memory_(memory), free_(free_function) {}
  ~SolverMemory() {
    if (memory_ != nullptr) free_(&memory_);
  }
  SolverMemory(const SolverMemory&) = delete;
  SolverMemory& operator=(const SolverMemory&) = delete;

  void* get() const { return memory_; }

 private:
  void* memory_;
  FreeFunction free_;
};

}  // namespace mbstream::sundials
