test_that("dentopo_vertices: per-vertex values that add up to the totals", {
  skip_without_dentopo()
  dir <- withr::local_tempdir()
  good <- write_sphere_ply(file.path(dir, "sphere.ply"))
  before <- list.files(tempdir(), pattern = "^dentopo-")
  v <- dentopo_vertices(good, bandwidth = 0.1)
  expect_equal(list.files(tempdir(), pattern = "^dentopo-"), before)  # cleaned up
  expect_equal(names(v), c("vertex", "x", "y", "z", "local_curvature", "local_dne", "sign"))
  expect_equal(nrow(v), 66L)
  expect_equal(v$vertex, 0:65)
  expect_true(all(v$sign %in% c(-1L, 1L)))
  row <- attr(v, "summary")
  expect_equal(row$bandwidth, 0.1)
  expect_equal(sum(abs(v$local_dne)), row$dne, tolerance = 1e-12)
  expect_equal(sum(v$local_dne[v$local_dne >= 0]), row$positive_dne, tolerance = 1e-12)
  expect_equal(-sum(v$local_dne[v$local_dne < 0]), row$negative_dne, tolerance = 1e-12)
  expect_equal(sqrt(v$x^2 + v$y^2 + v$z^2), rep(1, 66), tolerance = 1e-6)
})

test_that("dentopo_vertices: a file that fails is an error with the command's message", {
  skip_without_dentopo()
  dir <- withr::local_tempdir()
  bad <- file.path(dir, "bad.ply")
  writeLines("not a mesh", bad)
  before <- list.files(tempdir(), pattern = "^dentopo-")
  expect_error(dentopo_vertices(bad),
               "could not read mesh file '.*bad.ply': not a PLY file")
  expect_equal(list.files(tempdir(), pattern = "^dentopo-"), before)  # also after an error
  expect_error(dentopo_vertices(dir), "directory")
  expect_error(dentopo_vertices(c(bad, bad)), "one mesh file")
})
