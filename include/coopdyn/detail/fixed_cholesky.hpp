/// \file
/// \brief Deprecated (kept for one release): the fixed-size Cholesky factorisations moved to
/// `coopdyn/numerics/fixed_ldlt.hpp` (FixedLdlt, A = L D L^T) and `coopdyn/numerics/fixed_llt.hpp`
/// (FixedLlt, A = L L^T; DynamicLlt; Llt), namespace coopdyn; docs/numerics.md. This header
/// includes both and keeps the old detail:: names as aliases of the new ones.
#pragma once

#include "coopdyn/numerics/fixed_ldlt.hpp"
#include "coopdyn/numerics/fixed_llt.hpp"

namespace coopdyn::detail {

/// Deprecated: use coopdyn::FixedLdlt (the L D L^T factorisation this name always meant).
template <typename Scalar, int Size> using FixedCholesky = coopdyn::FixedLdlt<Scalar, Size>;
/// Deprecated: use coopdyn::FixedLlt.
template <typename Scalar, int Size> using FixedLlt = coopdyn::FixedLlt<Scalar, Size>;
/// Deprecated: use coopdyn::DynamicLlt.
template <typename MatrixType> using DynamicLlt = coopdyn::DynamicLlt<MatrixType>;
/// Deprecated: use coopdyn::Llt.
template <typename MatrixType> using Llt = coopdyn::Llt<MatrixType>;

}  // namespace coopdyn::detail
