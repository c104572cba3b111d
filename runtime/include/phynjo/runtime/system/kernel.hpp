#pragma once
/// \file
/// A model kernel loaded from a shared object (kernel_abi.h; docs/command-line.md, *Kernels*):
/// the same LagrangianSystem every integrator, event monitor, scene and sweep uses, its
/// functions calling the kernel's — one code path, not a second engine.
#include "phynjo/runtime/core/errors.hpp"
#include "phynjo/runtime/system/kernel_abi.h"
#include "phynjo/runtime/system/lagrangian_system.hpp"

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

namespace phynjo::runtime {

/// A kernel that cannot be loaded: the file (not there, not a shared object) or its table
/// (another ABI version, another table size); the message names the file and what is wrong.
class KernelError : public Error {
public:
    using Error::Error;
};

/// A loaded kernel (dlopen): shared by every system made from it, unloaded with the last.
class ModelKernel {
public:
    /// Loads `path` and checks its table (ABI version, size). Throws KernelError.
    static std::shared_ptr<const ModelKernel> load(const std::string& path);
    ~ModelKernel();
    ModelKernel(const ModelKernel&) = delete;
    ModelKernel& operator=(const ModelKernel&) = delete;

    [[nodiscard]] const phynjo_kernel& table() const noexcept { return *table_; }
    [[nodiscard]] const std::string& path() const noexcept { return path_; }
    [[nodiscard]] std::string_view name() const noexcept { return table_->model_name; }
    /// The index of a parameter (or input) by name; std::invalid_argument naming the model's
    /// parameters for another name.
    [[nodiscard]] std::size_t parameter_index(std::string_view name) const;
    /// Throws the typed error of a kernel status (SingularMassMatrix, SingularConstraints,
    /// NonFiniteResult, std::invalid_argument, std::out_of_range, Error) with its message;
    /// nothing for PHYNJO_OK.
    void check(int status) const;

private:
    ModelKernel(std::string path, void* handle, const phynjo_kernel* table)
        : path_(std::move(path)), handle_(handle), table_(table) {}
    std::string path_;
    void* handle_ = nullptr;
    const phynjo_kernel* table_ = nullptr;
};

/// A kernel's parameters (its opaque Parameters object): a value, at the file's defaults
/// when made; the kernel stays loaded while they live.
class KernelParameters {
public:
    explicit KernelParameters(std::shared_ptr<const ModelKernel> kernel);
    KernelParameters(const KernelParameters& other);
    KernelParameters& operator=(const KernelParameters& other);
    KernelParameters(KernelParameters&&) noexcept = default;
    KernelParameters& operator=(KernelParameters&&) noexcept = default;

    /// Sets a parameter or input (a derived one then stops following its definition);
    /// std::invalid_argument for an unknown name or a non-finite value.
    void set(std::string_view name, double value);
    void set(std::size_t k, double value);
    /// The value set, or the file's default (a derived one not set: its file default).
    [[nodiscard]] double get(std::string_view name) const;
    [[nodiscard]] double get(std::size_t k) const;
    [[nodiscard]] const void* data() const noexcept { return object_.get(); }
    [[nodiscard]] const std::shared_ptr<const ModelKernel>& kernel() const noexcept { return kernel_; }
    /// The object itself, shared (what a system holding a copy keeps).
    [[nodiscard]] std::shared_ptr<const void> shared() const noexcept { return object_; }

private:
    std::shared_ptr<const ModelKernel> kernel_;
    std::shared_ptr<void> object_;
};

/// The kernel's model for the runtime's integrators, bound to a copy of `P` (generated code's
/// `system(P)`).
LagrangianSystem kernel_system(const KernelParameters& P);
/// The same bound to *P, which must outlive it: changes between steps take effect (generated
/// code's `live_system(&P)`).
LagrangianSystem kernel_live_system(const KernelParameters* P);

} // namespace phynjo::runtime
