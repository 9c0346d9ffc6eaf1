// Eigen's dense kernels and decompositions for double matrices of dynamic size, compiled once for
// the whole program.
//
// A product of two MatrixXd, a matrix-vector product or a decomposition (QR, SVD, LDLT, ...)
// instantiates Eigen's out-of-line kernels (the blocked GEMM's packing and micro-kernel, GEMV) and
// the decomposition's compute() in every source that uses it: in the build's objects 9 copies of
// the GEMM kernel, 10 of each GEMV and 6 of ColPivHouseholderQR, 0.48 of Eigen's 0.81 MB of
// machine code duplicated (docs/bench.md, "Eigen's kernels compiled once"). This header declares
// those instantiations extern and eigen_instances.cc defines them, as json_instances.h does for
// JSON. The libraries' and tests' precompiled header includes it; a source compiled without it
// (the fuzz build, whose few batches hold few copies, -DZBRDF_PCH=OFF, clang's Python module)
// instantiates the templates itself, and the linker keeps one copy.
//
// What is named: class templates whose heavy members Eigen defines outside the class (so that an
// extern declaration keeps them from being compiled here), with the template arguments Eigen
// itself derives (gebp_traits), so that the declarations match on any SIMD width. Member
// templates (solve(), a HouseholderSequence's evalTo) and expression templates are instantiated
// where they are used, as before.
#pragma once

#include <Eigen/Dense>

namespace Eigen {
namespace internal {
namespace zbrdf_instances {
using Traits = gebp_traits<double, double>;
using ColMapper = const_blas_data_mapper<double, Index, ColMajor>;
using RowMapper = const_blas_data_mapper<double, Index, RowMajor>;
using Result = blas_data_mapper<double, Index, ColMajor, Unaligned, 1>;
}  // namespace zbrdf_instances

// The blocked matrix-matrix product (general_matrix_matrix_product): packing of either storage
// order and the micro-kernel.
extern template struct gebp_kernel<double, double, Index, zbrdf_instances::Result,
                                   zbrdf_instances::Traits::mr, zbrdf_instances::Traits::nr, false,
                                   false>;
extern template struct gemm_pack_lhs<
    double, Index, zbrdf_instances::ColMapper, zbrdf_instances::Traits::mr,
    zbrdf_instances::Traits::LhsProgress, zbrdf_instances::Traits::LhsPacket4Packing, ColMajor>;
extern template struct gemm_pack_lhs<
    double, Index, zbrdf_instances::RowMapper, zbrdf_instances::Traits::mr,
    zbrdf_instances::Traits::LhsProgress, zbrdf_instances::Traits::LhsPacket4Packing, RowMajor>;
extern template struct gemm_pack_rhs<double, Index, zbrdf_instances::ColMapper,
                                     zbrdf_instances::Traits::nr, ColMajor>;
extern template struct gemm_pack_rhs<double, Index, zbrdf_instances::RowMapper,
                                     zbrdf_instances::Traits::nr, RowMajor>;

// Matrix-vector products, with a column-major or row-major (transposed) matrix; the last
// (BuiltIn) is the one Eigen's triangular matrix-vector product calls.
extern template struct general_matrix_vector_product<
    Index, double, zbrdf_instances::ColMapper, ColMajor, false, double, zbrdf_instances::RowMapper,
    false, Specialized>;
extern template struct general_matrix_vector_product<
    Index, double, zbrdf_instances::RowMapper, RowMajor, false, double, zbrdf_instances::ColMapper,
    false, Specialized>;
extern template struct general_matrix_vector_product<
    Index, double, zbrdf_instances::ColMapper, ColMajor, false, double, zbrdf_instances::ColMapper,
    false, Specialized>;
extern template struct general_matrix_vector_product<Index, double, zbrdf_instances::RowMapper,
                                                     RowMajor, false, double,
                                                     zbrdf_instances::RowMapper, false, BuiltIn>;
}  // namespace internal

// The decompositions' out-of-line work on MatrixXd: only the members zbrdf calls. Instantiating
// the whole classes compiles every member of JacobiSVD and SelfAdjointEigenSolver, which nothing
// calls (this source: 41 s instead of 33 s under the fuzz build's sanitizers).
extern template void ColPivHouseholderQR<MatrixXd>::computeInPlace();
extern template JacobiSVD<MatrixXd, ColPivHouseholderQRPreconditioner>&
JacobiSVD<MatrixXd, ColPivHouseholderQRPreconditioner>::compute(const MatrixXd&, unsigned int);
namespace internal {
extern template void tridiagonalization_inplace<MatrixXd, VectorXd>(MatrixXd&, VectorXd&);
extern template ComputationInfo computeFromTridiagonal_impl<MatrixXd, VectorXd>(VectorXd&,
                                                                                VectorXd&, Index,
                                                                                bool, MatrixXd&);
}  // namespace internal
}  // namespace Eigen
