#include "gimbalsim/dynamics/simulator.hpp"

#include <cmath>
#include <stdexcept>

#include "gimbalsim/dynamics/integrator.hpp"
#include "gimbalsim/dynamics/saved_state.hpp"
#include "gimbalsim/dynamics/simulate.hpp"

namespace gimbalsim {

struct Simulator::Impl {
  explicit Impl(const Model& model) : m(model) {}
  virtual ~Impl() = default;
  virtual StepResult step(const Vec2& tau, long long n) noexcept = 0;
  virtual StepResult run(const double* tau, long long n, double* rows, long long& done) noexcept = 0;
  virtual Row output() noexcept = 0;
  virtual double time() const noexcept = 0;
  virtual SavedState save() const = 0;
  virtual void restore(const SavedState& saved) = 0;
  Model m;
};

namespace {

template <class V>
struct VariantSimulator final : Simulator::Impl {
  VariantSimulator(const Model& model, const InitialParams& init, const Vec2& tau0)
      : Simulator::Impl(model), d(m), s(initialState<V>(init)) {
    u.tau = tau0;
  }

  StepResult step(const Vec2& tau, long long n) noexcept override {
    u.tau = tau;
    const StepResult r = advanceSteps(m, d, s, u, k, k + n);
    k = std::llround(s.t / m.integrator.step);
    return r;
  }

  StepResult run(const double* tau, long long n, double* rows, long long& done) noexcept override {
    done = 0;
    for (long long i = 0; i < n; ++i) {
      u.tau = Vec2(tau[2 * i], tau[2 * i + 1]);
      const StepResult r = advanceSteps(m, d, s, u, k, k + 1);
      if (!r.ok()) return r;
      ++k;
      const Row row = observe(m, d, s, u);
      const double* p = rowData(row);
      std::copy(p, p + kNumColumns, rows + i * kNumColumns);
      ++done;
    }
    return {StepStatus::Ok, s.t};
  }

  Row output() noexcept override { return observe(m, d, s, u); }
  double time() const noexcept override { return s.t; }

  SavedState save() const override {
    SavedState out;
    out.variant = variantName(m);
    out.t = s.t;
    out.q.assign(s.q.data(), s.q.data() + V::NQ);
    out.v.assign(s.v.data(), s.v.data() + V::NV);
    out.in_contact.assign(s.in_contact.begin(), s.in_contact.end());
    out.v0.assign(s.v0.begin(), s.v0.end());
    out.friction_mode = s.friction_mode;
    out.vt_floor = s.vt_floor;
    out.h_next = s.h_next;
    return out;
  }

  void restore(const SavedState& in) override {
    checkSavedState(in, &m);  // from outside: validated like a scene, each field by name
    State<V> r;
    r.t = in.t;
    r.q = Eigen::Map<const typename State<V>::VecQ>(in.q.data());
    r.v = Eigen::Map<const typename State<V>::VecV>(in.v.data());
    for (int e = 0; e < V::NC; ++e) {  // sizes checked above
      r.in_contact[e] = in.in_contact[e];
      r.v0[e] = in.v0[e];
    }
    r.friction_mode = in.friction_mode;
    r.vt_floor = in.vt_floor;
    r.h_next = in.h_next;
    s = r;
    k = std::llround(s.t / m.integrator.step);  // advanceSteps puts t on the grid t = k h
  }

  Data<V> d;
  State<V> s;
  Input u;
  long long k = 0;  ///< steps taken: s.t = k sim.step
};

}  // namespace

Simulator::Simulator(const Scene& scene)
    : impl_(dispatchVariant(scene.model, [&](auto tag) -> std::unique_ptr<Impl> {
        return std::make_unique<VariantSimulator<decltype(tag)>>(scene.model, scene.run.initial,
                                                           scene.run.torque);
      })) {}

Simulator::~Simulator() = default;

const Model& Simulator::model() const { return impl_->m; }
double Simulator::time() const noexcept { return impl_->time(); }
StepResult Simulator::step(const Vec2& tau, long long n) noexcept { return impl_->step(tau, n); }
StepResult Simulator::run(const double* tau, long long n, double* rows, long long& done) noexcept {
  return impl_->run(tau, n, rows, done);
}
Row Simulator::output() noexcept { return impl_->output(); }
SavedState Simulator::save() const { return impl_->save(); }
void Simulator::restore(const SavedState& saved) { impl_->restore(saved); }

}  // namespace gimbalsim
