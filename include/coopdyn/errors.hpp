/// \file
/// \brief The exceptions coopdyn throws, one per layer of input (docs/conventions.md, "Errors").
///
/// - InvalidModel: a model parameter (object, end-effector, grasp, gravity, load-distribution
///   weights) refused when a Model or another model-like object is built.
/// - InvalidArgument: any other input refused at run time outside the per-tick path: data logs,
///   options, time steps, targets, sizes of per-call arguments.
///
/// Both carry, besides the message, the component ("object", "end effector", "model",
/// "simulator", "identification", ...), the parameter's name and the arm's index as fields, so a
/// caller (a scenario loader, a GUI) can point at the offending input without parsing what().
/// The per-tick path never throws: it is noexcept and reports failures as a status.
#pragma once

#include "coopdyn/config.hpp"

#include <stdexcept>
#include <string>
#include <utility>

namespace coopdyn {

/// Value of Error::arm() when the parameter belongs to no particular arm.
inline constexpr Index no_arm = -1;

/// \brief Base of coopdyn's exceptions. what() reads
/// "coopdyn: <arm i | component>: '<parameter>' <problem>".
class Error : public std::invalid_argument {
public:
    Error(std::string component, std::string parameter, Index arm, std::string problem)
        : std::invalid_argument(message(component, parameter, arm, problem)),
          component_(std::move(component)),
          parameter_(std::move(parameter)),
          problem_(std::move(problem)),
          arm_(arm)
    {
    }

    /// What was being built or called: "object", "end effector", "model", "load distribution",
    /// "simulator", "identification", ...
    const std::string& component() const noexcept { return component_; }
    /// The offending parameter's name, as spelled in the API ("mass", "grasp_body.orientation").
    const std::string& parameter() const noexcept { return parameter_; }
    /// What is wrong with it ("must be positive and finite, got -2").
    const std::string& problem() const noexcept { return problem_; }
    /// Index of the arm the parameter belongs to, or no_arm.
    Index arm() const noexcept { return arm_; }
    bool has_arm() const noexcept { return arm_ != no_arm; }

private:
    static std::string message(const std::string& component, const std::string& parameter, Index arm,
                               const std::string& problem)
    {
        const std::string where = arm != no_arm ? "arm " + std::to_string(arm) : component;
        return "coopdyn: " + where + ": '" + parameter + "' " + problem;
    }

    std::string component_;
    std::string parameter_;
    std::string problem_;
    Index arm_;
};

/// \brief A model parameter was refused when the model was built (see the file comment).
class InvalidModel : public Error {
public:
    using Error::Error;
};

/// \brief A run-time input other than a model parameter was refused (see the file comment).
class InvalidArgument : public Error {
public:
    using Error::Error;
};

}  // namespace coopdyn
