// rocking.errors: the two kinds of failure a user can meet, and their exit codes.
// InputError: something the user gave is wrong (a scene key, a record, a flag);
// the message is one line naming what and where; the app exits with code 2.
// RunError: a valid run that cannot finish (step-size underflow, max steps);
// the message names the time and phase; the app exits with code 3. A study
// whose rows are all written but some of whose runs failed exits with code 4.
module;
#include <stdexcept>
#include <string>
export module rocking.errors;

export namespace rocking {

inline constexpr int exit_input_error = 2;
inline constexpr int exit_run_error = 3;
// A study (many runs) wrote every row, but some of its runs failed.
inline constexpr int exit_jobs_failed = 4;

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class RunError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace rocking
