#include "rcfd/operator.hpp"

#include <stdexcept>

namespace rcfd {

PetscErrorCode Operator::view(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "%s\n", type().c_str()));
  PetscFunctionReturn(PETSC_SUCCESS);
}

void OperatorRegistry::add(const std::string &name, OperatorFactory factory,
                           const std::string &help) {
  if (name.empty() || name.find_first_of(", \t") != std::string::npos)
    throw std::invalid_argument("operator name '" + name + "' must be one word");
  entries[name] = {std::move(factory), help};
}

std::unique_ptr<Operator> OperatorRegistry::create(const std::string &name) const {
  const auto it = entries.find(name);
  if (it == entries.end())
    throw std::invalid_argument("-pipeline: unknown operator '" + name + "'; known operators: " +
                                listing());
  auto op = it->second.factory();
  op->setOptionsPrefix(name + "_");
  return op;
}

std::string OperatorRegistry::listing() const {
  std::string out;
  for (const auto &[name, e] : entries) out += (out.empty() ? "" : ", ") + name;
  return out;
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
  wantView.clear();
  for (auto &op : ops) {
    PetscBool flag = PETSC_FALSE;
    PetscCall(op->setFromOptions(comm));
    PetscCall(PetscOptionsGetBool(nullptr, op->optionsPrefix().c_str(), "-view", &flag, nullptr));
    wantView.push_back(flag);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Pipeline::setUp(const RunContext &ctx) {
  PetscFunctionBeginUser;
  PetscCheck(!isSetUp, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONGSTATE, "The pipeline is already set up");
  std::vector<std::unique_ptr<Operator>> kept;
  std::vector<bool> keptView;
  for (size_t k = 0; k < ops.size(); ++k) {
    if (!ops[k]->needed(ctx)) {
      left.push_back(ops[k]->type());
      continue;
    }
    PetscCall(ops[k]->setUp(ctx));
    kept.push_back(std::move(ops[k]));
    keptView.push_back(k < wantView.size() && wantView[k]);
  }
  ops = std::move(kept);
  wantView = std::move(keptView);
  isSetUp = true;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Pipeline::apply(const StepInfo &step, FractionState &state) {
  PetscFunctionBeginUser;
  for (auto &op : ops) PetscCall(op->apply(step, state));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode Pipeline::viewRequested(PetscViewer viewer) const {
  PetscFunctionBeginUser;
  for (size_t k = 0; k < ops.size(); ++k)
    if (k < wantView.size() && wantView[k]) PetscCall(ops[k]->view(viewer));
  PetscFunctionReturn(PETSC_SUCCESS);
}

bool Pipeline::conservesMass() const {
  for (const auto &op : ops)
    if (!op->conservesMass()) return false;
  return true;
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
