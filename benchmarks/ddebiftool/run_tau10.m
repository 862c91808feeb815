%% DDE-BIFTOOL cross-check of slopetui at tau=10, defaults, continuation in k
setup_path();
t0=tic;
deg=4; nint=60;
fprintf('collocation: degree %d, %d intervals (adaptive mesh)\n',deg,nint);
[pbr,funcs,ip,hopf]=psol_branch(10,5.5,struct('degree',deg,'intervals',nint,...
    'npts',120,'kmax',25.5,'maxstep',0.5));
[k,T,A,R,c]=orbit_measures(pbr.point,ip);
[~,ifold]=min(k);
fprintf('branch: %d points, k from %.4f down to %.4f and up to %.4f (%.0fs)\n',...
    numel(k),k(1),k(ifold),k(end),toc(t0));
%% fold of cycles
[kf,Tf,fine]=fold_refine(funcs,pbr,ip);
fprintf('FOLDFIT tau=10 k_fold=%.6f T_fold=%.6f (vertex of quadratic fit)\n',kf,Tf);
[kp,Tp,~,~,sp]=pofold_point(funcs,fine,ip);
fprintf('POFOLD tau=10 success=%d k_fold=%.8f T_fold=%.8f (SetupPOfold, extended system)\n',sp,kp,Tp);
[kk]=orbit_measures(fine.point,ip);
[~,~,~,fpts]=GetStability(fine,'funcs',funcs,'exclude_trivial',true,'locate_trivial',@(p)[1;1]);
fprintf('fine branch around fold: k, |mu| (4 largest; two are the trivial 1s)\n');
for i=1:numel(fpts)
    mu=fpts(i).stability.mu; [~,o]=sort(abs(mu),'descend');
    fprintf('  k=%.6f |mu|=%s\n',kk(i),mat2str(abs(mu(o(1:4)))',6));
end
%% orbits at fixed k, with Floquet multipliers
unst=1:ifold; stab=ifold:numel(k);
list={'unstable',2,unst;'unstable',4,unst;'unstable',6,unst;...
    'unstable',2.21090135,unst;'unstable',3.16771958,unst;'unstable',4.64879717,unst;...
    'unstable',5.71180719,unst;...
    'stable',2,stab;'stable',10,stab;'stable',15,stab;'stable',20,stab;'stable',25,stab};
fprintf('ORBITS (side, k, period, pp(m_y) on mesh, drift c, nontrivial |mu| largest 2, #|mu|>1 excl. 2 trivial)\n');
for i=1:size(list,1)
    [pt,suc]=orbit_at_k(funcs,pbr,ip,list{i,2},list{i,3});
    if ~suc, fprintf('  %s k=%g: correction failed\n',list{i,1},list{i,2}); continue; end
    pt.stability=p_stabil(funcs,pt,pbr.method.stability);
    mu=pt.stability.mu; [~,o]=sort(abs(mu-1)); triv=o(1:2); % two trivial multipliers (flow, translation)
    rest=mu(setdiff(1:numel(mu),triv)); [~,o2]=sort(abs(rest),'descend');
    [~,Tp,Ap,~,cp]=orbit_measures(pt,ip);
    fprintf('ORBIT %-8s k=%9.5f T=%.6f pp=%.6f c=%.4e |mu|=%s trivial_dev=%.1e n_unstable=%d\n',...
        list{i,1},list{i,2},Tp,Ap,cp,mat2str(abs(rest(o2(1:2)))',5),max(abs(mu(triv)-1)),sum(abs(rest)>1));
end
%% stability along the whole branch (excluding the 2 trivial multipliers)
[nunst,dom]=GetStability(pbr,'funcs',funcs,'exclude_trivial',true,'locate_trivial',@(p)[1;1]);
fprintf('branch stability: unstable part k in [%.4f, %.4f]: n_unstable=%s\n',...
    min(k(unst)),max(k(unst)),mat2str(unique(nunst(unst(2:end-1)))'));
fprintf('stable part k in [%.4f, %.4f]: n_unstable=%s, |dominant nontriv mu| range for k>=10: [%.4f, %.4f]\n',...
    min(k(stab(2:end))),max(k(stab)),mat2str(unique(nunst(stab(2:end)))'),...
    min(abs(dom(stab(k(stab)>=10)))),max(abs(dom(stab(k(stab)>=10)))));
fprintf('runtime %.0f s\n',toc(t0));
save('-binary','tau10_results.mat','pbr','fine','hopf','ip');
