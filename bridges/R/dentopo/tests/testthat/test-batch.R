test_that("dentopo_batch: one row per file, the command's columns, errors as rows", {
  skip_without_dentopo()
  dir <- withr::local_tempdir()
  good <- write_sphere_ply(file.path(dir, "sphere.ply"))
  bad <- file.path(dir, "bad, \"quoted\" \u00e9.ply")
  writeLines("not a mesh", bad)
  table <- dentopo_batch(c(good, bad))
  expect_s3_class(table, "data.frame")
  expect_equal(names(table), c(
    "file", "dne", "positive_dne", "negative_dne", "surface_area",
    "positive_surface_area", "negative_surface_area", "vertices", "faces",
    "bandwidth", "cutoff", "distance_type", "sign_method", "method", "protocol",
    "seconds", "status", "error", "warnings"))
  expect_equal(nrow(table), 2L)
  ok <- table[table$status == "ok", ]
  expect_equal(ok$file, good)
  expect_type(ok$dne, "double")
  expect_type(ok$vertices, "integer")
  expect_equal(ok$vertices, 66L)
  expect_true(is.na(ok$error))
  expect_equal(ok$positive_dne + ok$negative_dne, ok$dne, tolerance = 1e-12)
  failed <- table[table$status == "error", ]
  expect_equal(failed$file, bad)
  expect_match(failed$error, "bad, \"quoted\" \u00e9.ply", fixed = TRUE)
  expect_true(is.na(failed$dne))
})

test_that("options pass through: bandwidth, distance type, cutoff, columns", {
  skip_without_dentopo()
  dir <- withr::local_tempdir()
  good <- write_sphere_ply(file.path(dir, "sphere.ply"))
  table <- dentopo_batch(good, bandwidth = 0.1, distance_type = "geodesic", cutoff = 0.001)
  expect_equal(table$bandwidth, 0.1)
  expect_equal(table$cutoff, 0.001)
  expect_equal(table$distance_type, "geodesic")
  signdne <- dentopo_batch(good, columns = "signdne")
  expect_equal(names(signdne), c("File", "DNE", "positive_DNE", "negative_DNE",
                                 "surface_area", "positive_surface_area",
                                 "negative_surface_area"))
  expect_equal(signdne$DNE, signdne$positive_DNE + signdne$negative_DNE, tolerance = 1e-13)
})

test_that("a usage error stops with the command's message", {
  skip_without_dentopo()
  dir <- withr::local_tempdir()
  good <- write_sphere_ply(file.path(dir, "sphere.ply"))
  expect_error(dentopo_batch(good, no_such_option = 1),
               "usage error (exit status 2): dentopo: error: unrecognized arguments: --no-such-option",
               fixed = TRUE)
})

test_that("a name that a spreadsheet would run as a formula comes back as it was", {
  skip_without_dentopo()
  dir <- withr::local_tempdir()
  # the command writes these with a leading apostrophe (one more for "'quoted"),
  # which read_dentopo_csv removes
  names <- c("=1+2.ply", "@SUM(A1).ply", "-2.ply", "'quoted.ply")
  for (name in names) write_sphere_ply(file.path(dir, name))
  table <- dentopo_batch(file.path(dir, names), metrics = "classic", columns = "molar")
  expect_setequal(table$File, names)  # molaR's File column: base names
  expect_true(all(table$status == "ok"))
})

test_that("a vector for a two-value option is one pair: arc_range = c(low, high)", {
  skip_without_dentopo()
  dir <- withr::local_tempdir()
  good <- write_sphere_ply(file.path(dir, "sphere.ply"))
  wide <- dentopo_batch(good, metrics = "arc", arc_range = c(0.2, 0.8))
  default <- dentopo_batch(good, metrics = "arc")
  expect_equal(wide$status, "ok")
  expect_type(wide$arc, "double")
  expect_false(isTRUE(all.equal(wide$arc, default$arc)))
})
