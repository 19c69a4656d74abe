// A solver that counts its steps per call, as SUNDIALS' CVODE, ARKODE and IDA do, under the
// run's budgets, which are over the whole run: IntegratorBase::SolveInChunks calls it in
// chunks of steps while a CPU budget runs (CpuCheckPacer) and stops it where a budget is spent
// and the next output lies beyond its last internal step.
#pragma once

namespace mbstream {

class ChunkedSolver {
 public:
  virtual long NumSteps() const = 0;       // internal steps so far
  virtual double CurrentTime() const = 0;  // s, the solver's internal time
  // The per-call step limit of the next Solve (>= 1); throws InternalError when refused.
  virtual void LimitSteps(long steps) = 0;
  // One call of the solver in normal mode (interpolating at t_out), the state into the
  // integrator's output vector; the solver's flag (< 0: failure).
  virtual int Solve(double t_out, double* t_reached) = 0;
  // The flag Solve returns when its per-call step limit ran out.
  virtual int TooMuchWorkFlag() const = 0;

 protected:
  ~ChunkedSolver() = default;
};

// How IntegratorBase::SolveInChunks ended.
struct ChunkedSolve {
  int flag = 0;            // the solver's last flag; >= 0: t_out reached
  double t_reached = 0.0;  // s, where it stopped (flag < 0)
  // Whether the solver ran: y and t_reached are then its own after a failed call, else the
  // last output's.
  bool evolved = false;
  bool cpu_spent = false;  // the CPU budget stopped it
};

}  // namespace mbstream
