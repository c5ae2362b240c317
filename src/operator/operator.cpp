#include "rcfd/operator.hpp"
#include "base/petsc_compat.hpp"
#include "rcfd/observables.hpp"

namespace rcfd {

PetscErrorCode Operator::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "%s\n", type().c_str()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Operator::setFromOptions(MPI_Comm) { return PETSC_SUCCESS; }

PetscErrorCode Operator::restoreState(const std::vector<double> &state) {
  PetscFunctionBeginUser;
  PetscCheck(state.empty(), PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
             "The checkpoint holds state of the operator %s, which keeps none", type().c_str());
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Operator::monitors(const RunContext &, std::vector<OperatorMonitor> *) { return PETSC_SUCCESS; }

PetscErrorCode Operator::setUpInPipeline(const std::vector<Operator *> &) { return PETSC_SUCCESS; }

PetscErrorCode ShellOperator::setUp(const RunContext &) { return PETSC_SUCCESS; }

OperatorRegistry::OperatorRegistry() : makers("-pipeline", "operator") {}

namespace {
// A user's factory, as the registry keeps it (built-ins may take the registry).
PetscErrorCode maker(const std::string &name, OperatorFactory factory,
                     std::function<std::unique_ptr<Operator>(const OperatorRegistry &)> *out) {
  PetscFunctionBeginUser;
  PetscCheck(static_cast<bool>(factory), PETSC_COMM_SELF, PETSC_ERR_ARG_NULL,
             "Cannot register the operator '%s' without a factory", name.c_str());
  *out = [factory = std::move(factory)](const OperatorRegistry &) { return factory(); };
  PetscFunctionReturn(PETSC_SUCCESS);
}
} // namespace

PetscErrorCode OperatorRegistry::add(const std::string &name, OperatorFactory factory, const std::string &help) {
  Makers::Factory made;
  PetscFunctionBeginUser;
  PetscCall(maker(name, std::move(factory), &made));
  PetscCall(makers.add(name, std::move(made), help));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode OperatorRegistry::replace(const std::string &name, OperatorFactory factory, const std::string &help) {
  Makers::Factory made;
  PetscFunctionBeginUser;
  PetscCall(maker(name, std::move(factory), &made));
  PetscCall(makers.replace(name, std::move(made), help));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode OperatorRegistry::create(const std::string &name, std::unique_ptr<Operator> *op) const {
  PetscFunctionBeginUser;
  PetscCall(makers.create(name, op, *this));
  (*op)->setOptionsPrefix(name + "_");
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode OperatorRegistry::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(makers.view(viewer));
  PetscCall(carry.view(viewer));
  PetscCall(laws.view(viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Pipeline::add(std::unique_ptr<Operator> op) {
  PetscFunctionBeginUser;
  PetscCheck(!isSetUp, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONGSTATE,
             "Operators cannot be added to a pipeline after it is set up (adding '%s')",
             op->type().c_str());
  ops.push_back(std::move(op));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Pipeline::setFromOptions(MPI_Comm comm) {
  PetscFunctionBeginUser;
  views.clear();
  views.resize(ops.size());
  for (size_t k = 0; k < ops.size(); ++k) {
    PetscCall(ops[k]->setFromOptions(comm));
    PetscCall(PetscOptionsGetViewer(comm, nullptr, ops[k]->optionsPrefix().c_str(), "-view",
                                    views[k].viewer.put(), &views[k].format, nullptr));
    PetscBool ascii = PETSC_TRUE;
    if (views[k].viewer)
      PetscCall(PetscObjectTypeCompare((PetscObject)views[k].viewer.get(), PETSCVIEWERASCII, &ascii));
    PetscCheck(ascii, comm, PETSC_ERR_USER_INPUT,
               "-%sview prints text: give it no value (stdout) or ascii:FILE", ops[k]->optionsPrefix().c_str());
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Pipeline::setUp(const RunContext &ctx) {
  PetscFunctionBeginUser;
  PetscCheck(!isSetUp, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONGSTATE, "The pipeline is already set up");
  views.resize(ops.size()); // setFromOptions may not have run
  std::vector<std::unique_ptr<Operator>> kept;
  std::vector<RequestedView> keptViews;
  for (size_t k = 0; k < ops.size(); ++k) {
    if (!ops[k]->needed(ctx)) {
      left.push_back(ops[k]->type());
      continue;
    }
    PetscCall(ops[k]->setUp(ctx));
    kept.push_back(std::move(ops[k]));
    keptViews.push_back(std::move(views[k]));
  }
  ops = std::move(kept);
  views = std::move(keptViews);
  std::vector<Operator *> before;
  for (const auto &op : ops) {
    PetscCall(op->setUpInPipeline(before));
    before.push_back(op.get());
  }
  isSetUp = true;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Pipeline::apply(const StepInfo &step, FractionState &state) {
  PetscFunctionBeginUser;
  seconds.resize(ops.size(), 0.0);
  for (size_t k = 0; k < ops.size(); ++k) {
    const double start = MPI_Wtime();
    PetscCall(ops[k]->apply(step, state));
    seconds[k] += MPI_Wtime() - start;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Pipeline::viewRequested() const {
  PetscFunctionBeginUser;
  for (size_t k = 0; k < ops.size() && k < views.size(); ++k) {
    const RequestedView &v = views[k];
    if (!v.viewer) continue;
    PetscCall(PetscViewerPushFormat(v.viewer, v.format));
    PetscCall(ops[k]->view(v.viewer));
    PetscCall(PetscViewerPopFormat(v.viewer));
    PetscCall(PetscViewerFlush(v.viewer)); // a file is complete when the run ends
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

bool Pipeline::conservesMass() const {
  for (const auto &op : ops)
    if (!op->conservesMass()) return false;
  return true;
}

bool Pipeline::accountsMass() const {
  for (const auto &op : ops)
    if (!op->conservesMass() && !op->addedMass()) return false;
  return true;
}

namespace {
// The sum over the operators of what each says it added (a vector each, or nullptr).
template <class Get>
void sumAdded(const std::vector<std::unique_ptr<Operator>> &ops, Get get, std::vector<double> *sum) {
  sum->clear();
  for (const auto &op : ops) {
    const std::vector<double> *added = get(*op);
    if (!added) continue;
    sum->resize(added->size(), 0.0);
    for (std::size_t k = 0; k < added->size(); ++k) (*sum)[k] += (*added)[k];
  }
}
} // namespace

void Pipeline::addedMass(std::vector<double> *perFraction) const {
  sumAdded(ops, [](const Operator &op) { return op.addedMass(); }, perFraction);
}

void Pipeline::addedAmounts(std::vector<double> *perScalarFraction) const {
  sumAdded(ops, [](const Operator &op) { return op.addedAmounts(); }, perScalarFraction);
}

PetscErrorCode Pipeline::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "Pipeline of %zu operators\n", ops.size()));
  PetscCall(PetscViewerASCIIPushTab(viewer));
  for (const auto &op : ops) PetscCall(op->view(viewer));
  for (const auto &name : left)
    PetscCall(PetscViewerASCIIPrintf(viewer, "(%s left out: not needed by this case)\n", name.c_str()));
  PetscCall(PetscViewerASCIIPopTab(viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

} // namespace rcfd
