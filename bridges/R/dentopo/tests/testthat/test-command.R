test_that("no working command: one error that says how to install it", {
  withr::local_options(dentopo.command = file.path(tempdir(), "no-such-dentopo"))
  withr::local_envvar(DENTOPO = "", PATH = tempdir())
  expect_error(dentopo_command(), "pip install dentopo")
  expect_error(dentopo_command(), "options\\(dentopo.command\\)")
})

test_that("a setting that does not work gives way to the next, with a warning", {
  skip_without_dentopo()
  env <- Sys.getenv("DENTOPO")
  skip_if(!nzchar(env), "DENTOPO not set")
  withr::local_options(dentopo.command = file.path(tempdir(), "no-such-dentopo"))
  expect_warning(cmd <- dentopo_command(), "DENTOPO")
  expect_true(length(cmd) >= 1L)
})

test_that("the option comes before the environment variable", {
  skip_without_dentopo()
  env <- Sys.getenv("DENTOPO")
  skip_if(!nzchar(env), "DENTOPO not set")
  withr::local_options(dentopo.command = env)
  withr::local_envvar(DENTOPO = file.path(tempdir(), "no-such-dentopo"))
  expect_silent(cmd <- dentopo_command())
  expect_equal(cmd, dentopo:::split_command(env))
})
