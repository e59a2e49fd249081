// rocking.sundials: the reference integrators behind the rocking.integrator
// interface (right-hand side, guards with directions, breakpoints as stop
// times, reset with re-initialisation, statistics), and the factory that picks
// a backend by name. SUNDIALS 6.4 (Hindmarsh et al., ACM TOMS 31, 2005):
//   cvode:  CVODE, variable-order BDF with a dense direct linear solver and
//           its own root finding (CVodeRootInit);
//   arkode: ARKODE ERKStep with the Dormand-Prince 7-4-5 table, the same
//           method as rk45, independently implemented.
// Everything SUNDIALS allocates is owned by RAII handles; no void* or integer
// return code leaves this module: failures become IntegrationError.
module;
#include <rocking/eigen.hpp>
#include <memory>
#include <string>
#include <string_view>
export module rocking.sundials;
export import rocking.integrator;

export namespace rocking::ode {

// automatic: the caller picks rk45 or rosw for its system (the factory alone,
// knowing nothing of it, makes rk45).
enum class Backend { rk45, cvode, arkode, rosw, automatic };

// "rk45", "rosw", "cvode", "arkode", "auto"; throws InputError naming the choices otherwise.
Backend parse_backend(std::string_view name);
std::string_view backend_name(Backend b);

std::unique_ptr<Integrator> make_cvode(Eigen::Index n, Rhs rhs, Options options);
std::unique_ptr<Integrator> make_arkode(Eigen::Index n, Rhs rhs, Options options);
// The backend b; rosw (rocking.integrator's Rosenbrock-W) solves with `stiff`,
// the others do not use it.
std::unique_ptr<Integrator> make_integrator(Backend b, Eigen::Index n, Rhs rhs, Options options,
                                            LinearSolve stiff = {});

}  // namespace rocking::ode
