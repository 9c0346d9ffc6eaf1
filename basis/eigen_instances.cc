#include "basis/eigen_instances.h"

namespace Eigen {
namespace internal {
template struct gebp_kernel<double, double, Index, zbrdf_instances::Result,
                            zbrdf_instances::Traits::mr, zbrdf_instances::Traits::nr, false, false>;
template struct gemm_pack_lhs<double, Index, zbrdf_instances::ColMapper,
                              zbrdf_instances::Traits::mr, zbrdf_instances::Traits::LhsProgress,
                              zbrdf_instances::Traits::LhsPacket4Packing, ColMajor>;
template struct gemm_pack_lhs<double, Index, zbrdf_instances::RowMapper,
                              zbrdf_instances::Traits::mr, zbrdf_instances::Traits::LhsProgress,
                              zbrdf_instances::Traits::LhsPacket4Packing, RowMajor>;
template struct gemm_pack_rhs<double, Index, zbrdf_instances::ColMapper,
                              zbrdf_instances::Traits::nr, ColMajor>;
template struct gemm_pack_rhs<double, Index, zbrdf_instances::RowMapper,
                              zbrdf_instances::Traits::nr, RowMajor>;
template struct general_matrix_vector_product<Index, double, zbrdf_instances::ColMapper, ColMajor,
                                              false, double, zbrdf_instances::RowMapper, false,
                                              Specialized>;
template struct general_matrix_vector_product<Index, double, zbrdf_instances::RowMapper, RowMajor,
                                              false, double, zbrdf_instances::ColMapper, false,
                                              Specialized>;
template struct general_matrix_vector_product<Index, double, zbrdf_instances::ColMapper, ColMajor,
                                              false, double, zbrdf_instances::ColMapper, false,
                                              Specialized>;
template struct general_matrix_vector_product<Index, double, zbrdf_instances::RowMapper, RowMajor,
                                              false, double, zbrdf_instances::RowMapper, false,
                                              BuiltIn>;
}  // namespace internal

template void ColPivHouseholderQR<MatrixXd>::computeInPlace();
template JacobiSVD<MatrixXd, ColPivHouseholderQRPreconditioner>&
JacobiSVD<MatrixXd, ColPivHouseholderQRPreconditioner>::compute(const MatrixXd&, unsigned int);
namespace internal {
template void tridiagonalization_inplace<MatrixXd, VectorXd>(MatrixXd&, VectorXd&);
template ComputationInfo computeFromTridiagonal_impl<MatrixXd, VectorXd>(VectorXd&, VectorXd&,
                                                                         Index, bool, MatrixXd&);
}  // namespace internal
}  // namespace Eigen
