-- Headless Neovim (0.7.2 API) end-to-end test of higraph-lsp with a real editor's LSP
-- client (tooling.md §7). Run by tests/nvim/run.sh, which sets:
--   HIGRAPH_LSP  the server binary
--   HIGRAPH_WS   a copy of examples/drilling, plus graphs/kaputt.higraph (a syntax error)
--
-- Steps: start the server on the workspace and open the valve graph; wait for the
-- diagnostics of the broken file, which is never opened; type an error into the open
-- buffer and wait for its diagnostic, then undo it and wait until it is gone; rename the
-- message variable IM_Ab of Ventil_2E with textDocument/rename; apply the workspace edit and
-- check that the group file, which was never opened, now says Vorschub.IM_Senken.
-- Any failure ends Neovim with `cquit` (exit status 1).

local server = os.getenv("HIGRAPH_LSP")
local root = os.getenv("HIGRAPH_WS")

local function fail(message)
  io.stderr:write("nvim test FAILED: " .. message .. "\n")
  vim.cmd("cquit 1")
end

local function step(message)
  io.stdout:write("nvim test: " .. message .. "\n")
end

local function wait(what, condition)
  if not vim.wait(30000, condition, 50) then
    fail("timed out waiting for " .. what)
  end
end

local function run()
  if not server or not root then
    fail("HIGRAPH_LSP and HIGRAPH_WS must be set")
  end

  local client_id = vim.lsp.start_client({
    name = "higraph",
    cmd = { server, "lsp", "--stdio" },
    root_dir = root,
  })
  if not client_id then
    fail("the server did not start")
  end

  local ventil = root .. "/graphs/ventil_2e.higraph"
  vim.cmd("edit " .. vim.fn.fnameescape(ventil))
  local buf = vim.api.nvim_get_current_buf()
  vim.lsp.buf_attach_client(buf, client_id)
  local client = vim.lsp.get_client_by_id(client_id)
  wait("initialization", function()
    return client.initialized
  end)
  step("initialized")

  -- Diagnostics of a workspace file that is not open.
  local broken = vim.uri_to_bufnr(vim.uri_from_fname(root .. "/graphs/kaputt.higraph"))
  wait("the diagnostics of the unopened broken file", function()
    for _, d in ipairs(vim.diagnostic.get(broken)) do
      if d.code == "HG0009" or (d.user_data and d.user_data.lsp and d.user_data.lsp.code == "HG0009") then
        return true
      end
    end
    return false
  end)
  step("diagnostics of an unopened file arrived")

  -- An edit in the open buffer (incremental sync): an unlexable character.
  local last = vim.api.nvim_buf_line_count(buf)
  vim.api.nvim_buf_set_lines(buf, last, last, false, { "$" })
  wait("the diagnostic of the edit", function()
    return #vim.diagnostic.get(buf, { severity = vim.diagnostic.severity.ERROR }) > 0
  end)
  step("an edit produced a diagnostic")
  vim.api.nvim_buf_set_lines(buf, last, last + 1, false, {})
  wait("the diagnostic to go away", function()
    return #vim.diagnostic.get(buf, { severity = vim.diagnostic.severity.ERROR }) == 0
  end)
  step("undoing the edit cleared it")

  -- Rename IM_Ab at its declaration.
  local line, column
  for i, text in ipairs(vim.api.nvim_buf_get_lines(buf, 0, -1, false)) do
    local at = text:find("IM_Ab : BOOL msg in", 1, true)
    if at then
      line, column = i - 1, at - 1
      break
    end
  end
  if not line then
    fail("no declaration of IM_Ab in " .. ventil)
  end
  local params = {
    textDocument = { uri = vim.uri_from_bufnr(buf) },
    position = { line = line, character = column },
    newName = "IM_Senken",
  }
  local response = client.request_sync("textDocument/rename", params, 30000, buf)
  if not response or response.err or not response.result then
    fail("rename failed: " .. vim.inspect(response))
  end
  local group_uri = vim.uri_from_fname(root .. "/bohrmaschine.higraph")
  local changes = response.result.changes or {}
  local group_edits = changes[group_uri]
  if not group_edits or #group_edits == 0 then
    fail("the rename does not edit the group file: " .. vim.inspect(response.result))
  end
  step("rename returned " .. #group_edits .. " edit(s) for the group file")

  vim.lsp.util.apply_workspace_edit(response.result, client.offset_encoding or "utf-16")
  local group_buf = vim.uri_to_bufnr(group_uri)
  vim.fn.bufload(group_buf)
  local group_text = table.concat(vim.api.nvim_buf_get_lines(group_buf, 0, -1, false), "\n")
  if not group_text:find("OM_Senken     := Vorschub.IM_Senken;", 1, true) then
    fail("the group file does not say Vorschub.IM_Senken:\n" .. group_text)
  end
  if group_text:find("Vorschub.IM_Ab", 1, true) then
    fail("the group file still says Vorschub.IM_Ab")
  end
  local ventil_text = table.concat(vim.api.nvim_buf_get_lines(buf, 0, -1, false), "\n")
  local _, uses = ventil_text:gsub("IM_Senken", "")
  if uses ~= 3 then
    fail("expected 3 occurrences of IM_Senken in the valve graph, found " .. uses)
  end
  step("the workspace edit renamed Vorschub.IM_Ab in the group file")

  vim.lsp.stop_client(client_id)
  step("passed")
  vim.cmd("qall!")
end

local ok, error = pcall(run)
if not ok then
  fail(tostring(error))
end
