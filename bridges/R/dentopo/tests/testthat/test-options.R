# How R arguments become command line options (no command needed).

test_that("named arguments become --options, dashes for underscores and dots", {
  expect_equal(dentopo:::as_option("distance_type", "geodesic"),
               c("--distance-type", "geodesic"))
  expect_equal(dentopo:::as_option("opcr.steps", 8), c("--opcr-steps", "8"))
  expect_equal(dentopo:::as_option("find_alpha", TRUE), "--find-alpha")
  expect_equal(dentopo:::as_option("find_alpha", FALSE), character())
  expect_equal(dentopo:::as_option("columns", NULL), character())
  expect_equal(dentopo:::as_option("metrics", c("slope", "opc")),
               c("--metrics", "slope,opc"))
})

test_that("numbers are written with every digit needed to read them back", {
  for (x in c(0.08, 0.1 + 0.2, 1 / 3, 1e-300, 123456789, 2^60, -0.5)) {
    text <- dentopo:::format_number(x)
    expect_identical(as.numeric(text), x)
  }
  expect_equal(dentopo:::format_number(0.08), "0.08")
  expect_equal(dentopo:::format_number(4), "4")
})

test_that("unnamed or unusable option values are refused", {
  expect_error(dentopo:::as_options(list(1)), "must be named")
  expect_error(dentopo:::as_option("bandwidth", list(1)), "--bandwidth")
  expect_error(dentopo_batch("x.ply", output = "t.csv"), "write.csv")
  expect_error(dentopo_batch(NA_character_), "character vector")
})

test_that("paths go after --, so odd names stay paths", {
  expect_equal(dentopo:::as_paths(c("-x.ply", "robustness")), c("--", "-x.ply", "robustness"))
})

test_that("the command's message on a usage error drops argparse's usage block", {
  said <- c("usage: dentopo [-h] [--samples]", "               [PATH ...]",
            "dentopo: error: unrecognized arguments: --nonsense")
  expect_equal(dentopo:::command_message(said),
               "dentopo: error: unrecognized arguments: --nonsense")
})
